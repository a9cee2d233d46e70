#!/usr/bin/env bash
# The main job: set up and build, then encode a bundled 128x128 texture into
# a .vqt file (an AV1 atlas, the default) and decode a larger tileable texture from it,
# printing sizes, times and where the outputs went.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VQTEX_BUILD_DIR:-$root/build}"
"$root/scripts/setup.sh"
"$root/scripts/build.sh" >/dev/null
mkdir -p "$root/out"
input="$root/corpus/cellular_128.png"
file="$root/out/cellular.vqt"
output="$root/out/cellular_512.png"
"$build/vqtex-encode" "$input" "$file"
"$build/vqtex-decode" "$file" "$output" --size 512x512
"$build/vqtex-info" "$file" | sed -n '1,14p'
echo "example   $input: $(stat -c %s "$input") bytes as PNG"
echo "atlas     $file: $(stat -c %s "$file") bytes"
echo "texture   $output: 512x512, tiles seamlessly ($(stat -c %s "$output") bytes as PNG)"
