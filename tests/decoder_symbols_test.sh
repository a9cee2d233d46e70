#!/usr/bin/env bash
# Lists the symbols of the decoder library (static or shared) and fails on
# any that belongs to the encoder: what vqtex_decoder defines must read
# files and synthesise, never write, compress, train, fill or check an
# encoder's params; and nothing in it may call zstd's compressor or libaom.
# Usage: decoder_symbols_test.sh LIBRARY (libvqtex_decoder.a or .so)
set -euo pipefail
lib="$1"
[ -f "$lib" ] || { echo "decoder symbols: no library at $lib" >&2; exit 1; }

# Defined symbols, demangled (a shared library's own table: hidden ones too).
defined="$(nm -C --defined-only "$lib" 2>/dev/null | awk 'NF >= 3 { $1 = ""; $2 = ""; sub(/^  /, ""); print }')"
undefined="$(nm -C --undefined-only "$lib" 2>/dev/null | awk '{ print $NF }')"
[ -n "$defined" ] || { echo "decoder symbols: nm found no symbols in $lib" >&2; exit 1; }

# What the encoder defines, by name (ERE over demangled names; C functions
# demangle to their bare names).
forbidden=(
  '(^|[^A-Za-z_])encode_'                          # encode_model, encode_tree, encode_atlas_file, ...
  'Writer'                                         # ContainerWriter, ByteWriter
  '(^|[^e])compress'                               # zstd_compress (decompress is the decoder's)
  'aom_|av1_'                                      # libaom, linked in
  'ZSTD_(compress|createCCtx|CCtx)'                # zstd's compressor, linked in
  'validate_encode|validate_volume_synthesis'
  'validate\(vqtex_(model|synth|encode|volume_encode|fill)_params'
  'encode_settings_of|EncodeSettings'
  'write_(tree|histogram|level_coding)|level_section|model_header'
  '^vqtex_(encode|encode_volume|synthesize|synthesize_volume|fill|extend)$'
  '^vqtex_(encode|volume_encode|synth|fill|model)_params_'
  'vqtex::(train_codebook|train_params_for|choose_training_subset|analyse_example|analyse_volume|plan_model)'
  'vqtex::(choose_atlas|AtlasChoice|fill_region|raster_order|spiral_order|strip_temporal_delimiters)'
  'ExhaustiveMatcher'
  'vqtex_metrics::'
)
# What the decoder may not call: the compressor and the AV1 encoder.
forbidden_calls='^(ZSTD_compress|ZSTD_createCCtx|ZSTD_compressCCtx|ZSTD_compressStream|aom_)'

status=0
for pattern in "${forbidden[@]}"; do
  hits="$(printf '%s\n' "$defined" | grep -E -e "$pattern" || true)"
  if [ -n "$hits" ]; then
    echo "decoder symbols: $lib defines encoder symbols (pattern $pattern):" >&2
    printf '%s\n' "$hits" | head -20 | sed 's/^/  /' >&2
    status=1
  fi
done
calls="$(printf '%s\n' "$undefined" | grep -E -e "$forbidden_calls" || true)"
if [ -n "$calls" ]; then
  echo "decoder symbols: $lib calls the encoder's libraries:" >&2
  printf '%s\n' "$calls" | head -20 | sed 's/^/  /' >&2
  status=1
fi
[ "$status" -eq 0 ] && echo "decoder symbols: $lib defines $(printf '%s\n' "$defined" | wc -l) symbols, none of the encoder's"
exit "$status"
