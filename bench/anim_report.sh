#!/usr/bin/env bash
# anim_report.sh - animated textures (paper section 5.2) measured on the
# corpus animations: the coherent engine (vqtex-synth on the frame sequence)
# against the file path (vqtex-encode with default settings, then
# vqtex-decode), scored by anim-metrics (per-frame SWD against the example's
# frames, frame-to-frame change against the example's, the loop), with
# contact sheets (example row above the two outputs' rows).
#
# Usage: bench/anim_report.sh BUILD_DIR [OUT_DIR] [SIZE] [SEEDS]
#   BUILD_DIR  a build of this repository (vqtex-synth, vqtex-encode,
#              vqtex-decode, anim-metrics)
#   OUT_DIR    where frames, sheets and table.md go (default: anim_report)
#   SIZE       output frame size (default 128x128); 32 frames, as the examples
#   SEEDS      how many seeds to run (default 3: seeds 1..3)
# Needs oiiotool for the sheets. Everything runs on one thread.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(cd "${1:?usage: anim_report.sh BUILD_DIR [OUT_DIR] [SIZE] [SEEDS]}" && pwd)"
out="${2:-anim_report}"
size="${3:-128x128}"
seeds="${4:-3}"
mkdir -p "$out"
table="$out/table.md"
{
  echo "| animation | method | seed | SWD per frame | SWD floor | change | example change | ratio | loop | example loop | seconds |"
  echo "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
} > "$table"
field() { sed -E "s/.*\"$1\":([^,}]*).*/\1/" <<< "$2"; }
row() {  # name method seed seconds folder
  local m
  m="$("$build/anim-metrics" "$root/corpus/$1/frame_%03d.png" "$5/f_%03d.png")"
  echo "| $1 | $2 | $3 | $(field swd "$m") | $(field swd_floor "$m") | $(field change "$m") |" \
       "$(field example_change "$m") | $(field change_ratio "$m") | $(field loop "$m") | $(field example_loop "$m") | $4 |" >> "$table"
}
for name in waves_48_anim flicker_32_anim advected_32_anim; do
  example="$root/corpus/$name/frame_%03d.png"
  for seed in $(seq 1 "$seeds"); do
    dir="$out/$name/coherent_s$seed"; rm -rf "$dir"; mkdir -p "$dir"
    t0=$(date +%s.%N)
    "$build/vqtex-synth" "$example" "$dir/f_%03d.png" --size "$size" --seed "$seed" -j 1 --quiet
    t1=$(date +%s.%N)
    row "$name" coherent "$seed" "$(printf %.2f "$(echo "$t1 - $t0" | bc)")" "$dir"
    dir="$out/$name/file_s$seed"; rm -rf "$dir"; mkdir -p "$dir"
    t0=$(date +%s.%N)
    "$build/vqtex-encode" "$example" "$out/$name.vqt" --quiet --seed "$seed"
    "$build/vqtex-decode" "$out/$name.vqt" "$dir/f_%03d.png" --size "$size" -j 1 --quiet
    t1=$(date +%s.%N)
    row "$name" file "$seed" "$(printf %.2f "$(echo "$t1 - $t0" | bc)")" "$dir"
  done
  # Contact sheet: every fourth frame, twice the size; the example (tiled
  # 5x5 and cut to the output's size: the corpus animations tile), then
  # seed 1 of the coherent engine, then seed 1 of the file path.
  pick=(0 4 8 12 16 20 24 28)
  w="${size%x*}"; h="${size#*x}"
  args=()
  for t in "${pick[@]}"; do
    f="$(printf "$example" "$t")"
    tiles=(); for i in $(seq 25); do tiles+=("$f"); done
    oiiotool "${tiles[@]}" --mosaic 5x5 --cut "${w}x${h}+0+0" -o "$out/$name/ex_$t.png"
    args+=("$out/$name/ex_$t.png")
  done
  for src in "$out/$name/coherent_s1/f_%03d.png" "$out/$name/file_s1/f_%03d.png"; do
    for t in "${pick[@]}"; do args+=("$(printf "$src" "$t")"); done
  done
  oiiotool "${args[@]}" --mosaic:pad=4 "${#pick[@]}x3" --resample 200% -o "$out/${name}_sheet.png"
done
cat "$table"
