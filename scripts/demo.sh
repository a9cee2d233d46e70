#!/usr/bin/env bash
# The main job: set up, build, then synthesise a large tileable texture from
# a small one in corpus/, printing sizes, times and where the output went.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VQTEX_BUILD_DIR:-$root/build}"
"$root/scripts/setup.sh"
"$root/scripts/build.sh" >/dev/null
mkdir -p "$root/out"
input="$root/corpus/cellular_128.png"
output="$root/out/cellular_512.png"
"$build/vqtex-synth" "$input" "$output" --size 512x512 --seed 7
echo "input     $(stat -c %s "$input") bytes"
echo "output    $(stat -c %s "$output") bytes -> $output (tiles seamlessly)"
