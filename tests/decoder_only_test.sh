#!/usr/bin/env bash
# Configures and builds the source tree with VQTEX_DECODER_ONLY=ON in a
# temporary directory; checks that no encoder, trainer, filler, benchmark or
# internal library was built and that the decoder library holds no encoder
# symbol (decoder_symbols_test.sh); then decodes a file with the
# decoder-only programs. The library is built shared, so that the suite also
# checks that a shared library exports the C API only (exports_test.sh).
# Usage: decoder_only_test.sh SOURCE_DIR FILE.vqt
set -euo pipefail
src="$1"
file="$2"
build="$(mktemp -d)"
trap 'rm -rf "$build"' EXIT
cmake -S "$src" -B "$build" -DCMAKE_BUILD_TYPE=Release -DVQTEX_DECODER_ONLY=ON -DBUILD_SHARED_LIBS=ON >/dev/null
cmake --build "$build" -j 2 >/dev/null
for absent in vqtex-encode vqtex-synth vqtex-fill vqtex-bench libvqtex.a libvqtex.so libvqtex_internal.a \
              libvqtex_metrics.a; do
  if [ -e "$build/$absent" ] || [ -e "$build/metrics/$absent" ]; then
    echo "decoder-only build made $absent" >&2
    exit 1
  fi
done
library="$(find "$build" -maxdepth 1 \( -name libvqtex_decoder.a -o -name libvqtex_decoder.so \) | head -1)"
[ -n "$library" ] || { echo "decoder-only build made no libvqtex_decoder" >&2; exit 1; }
"$src/tests/decoder_symbols_test.sh" "$library"
"$src/tests/exports_test.sh" "$library"
"$build/decode_to_pam" "$file" "$build/out.pam" 32 32
"$build/vqtex-decode" "$file" "$build/out.png" --size 32x32
"$build/vqtex-info" "$file" >/dev/null
echo "decoder-only build: shared library (no encoder symbols, exports vqtex_* only), decode_to_pam, vqtex-decode and vqtex-info built and ran"
