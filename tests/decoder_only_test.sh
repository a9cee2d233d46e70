#!/usr/bin/env bash
# Configures and builds the source tree with VQTEX_DECODER_ONLY=ON in a
# temporary directory, checks that no encoder, trainer or filler was built,
# and decodes a file with the decoder-only programs.
# Usage: decoder_only_test.sh SOURCE_DIR FILE.vqt
set -euo pipefail
src="$1"
file="$2"
build="$(mktemp -d)"
trap 'rm -rf "$build"' EXIT
cmake -S "$src" -B "$build" -DCMAKE_BUILD_TYPE=Release -DVQTEX_DECODER_ONLY=ON >/dev/null
cmake --build "$build" -j 2 >/dev/null
for absent in vqtex-encode vqtex-synth vqtex-fill vqtex-bench libvqtex.a; do
  if [ -e "$build/$absent" ]; then
    echo "decoder-only build made $absent" >&2
    exit 1
  fi
done
"$build/decode_to_pam" "$file" "$build/out.pam" 32 32
"$build/vqtex-decode" "$file" "$build/out.png" --size 32x32
"$build/vqtex-info" "$file" >/dev/null
echo "decoder-only build: library, decode_to_pam, vqtex-decode and vqtex-info built and ran"
