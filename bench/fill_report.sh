#!/usr/bin/env bash
# fill_report.sh - hole filling (paper section 5.1) on photographed textures:
# vqtex-fill (two-pass, and the single-pass causal reference) against G'MIC's
# patch-based inpainting, with times and the boundary statistic of
# metrics/fill_seams.cpp.
#
# Usage: bench/fill_report.sh BUILD_DIR [OUT_DIR] [TEXTURE...]
#   BUILD_DIR  a build of this repository (vqtex-fill, fill-seams)
#   OUT_DIR    where images and table.md go (default: fill_report)
#   TEXTURE    names in ../shared/corpus without _256.png
#              (default: skimage_brick stk_pavingstones stk_rockwall mate_grass)
# Needs oiiotool and gmic (scripts/setup-bench.sh installs both). Every
# program runs on one thread (vqtex -j 1, OMP_NUM_THREADS=1 for G'MIC).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(cd "${1:?usage: fill_report.sh BUILD_DIR [OUT_DIR] [TEXTURE...]}" && pwd)"
out="${2:-fill_report}"
shift $(( $# >= 2 ? 2 : 1 ))
textures=("$@")
[ ${#textures[@]} -eq 0 ] && textures=(skimage_brick stk_pavingstones stk_rockwall mate_grass)
corpus="${VQTEX_SHARED_CORPUS:-$root/../shared/corpus}"
for tool in oiiotool gmic; do
  command -v "$tool" >/dev/null || { echo "fill_report: $tool not found (run scripts/setup-bench.sh)" >&2; exit 1; }
done
[ -d "$corpus" ] || { echo "fill_report: no corpus at $corpus (set VQTEX_SHARED_CORPUS)" >&2; exit 1; }
mkdir -p "$out"

# Masks for 256x256 images: a 64x64 hole in the middle and a 3-pixel-wide
# diagonal scratch across the image.
oiiotool --pattern constant:color=0 256x256 1 --box:color=1:fill=1 96,96,159,159 -d uint8 -o "$out/mask_hole64.png"
oiiotool --pattern constant:color=0 256x256 1 --line:color=1 10,30,240,200 --line:color=1 11,30,241,200 \
  --line:color=1 12,30,242,200 -d uint8 -o "$out/mask_scratch.png"

seconds() { date +%s.%N; }
table="$out/table.md"
{
  echo "| texture | mask | method | seconds | ratio leading | ratio trailing | exceed leading | exceed trailing |"
  echo "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |"
} > "$table"
row() {  # texture mask method seconds image mask_file
  read -r _all lead trail _eall elead etrail < <("$build/fill-seams" "$5" "$6")
  printf '| %s | %s | %s | %.2f | %s | %s | %s | %s |\n' "$1" "$2" "$3" "$4" "$lead" "$trail" "$elead" "$etrail" >> "$table"
}

for t in "${textures[@]}"; do
  img="$corpus/${t}_256.png"
  [ -f "$img" ] || { echo "fill_report: missing $img" >&2; exit 1; }
  for m in hole64 scratch; do
    mask="$out/mask_$m.png"
    # The damaged input: black under the mask (neither method may use it).
    damaged="$out/${t}_${m}_input.png"
    oiiotool "$img" --ch 0,1,2 "$mask" --ch 0,0,0 --invert --mul -d uint8 -o "$damaged"
    for method in two-pass causal; do
      result="$out/${t}_${m}_vqtex_${method}.png"
      t0=$(seconds)
      "$build/vqtex-fill" "$damaged" "$mask" "$result" --method "$method" -j 1 --quiet
      t1=$(seconds)
      row "$t" "$m" "vqtex $method" "$(awk "BEGIN { print $t1 - $t0 }")" "$result" "$mask"
    done
    result="$out/${t}_${m}_gmic.png"
    t0=$(seconds)
    OMP_NUM_THREADS=1 gmic -v -1 "$damaged" "$mask" inpaint_matchpatch[0] [1] keep[0] o "$result"
    t1=$(seconds)
    row "$t" "$m" "gmic inpaint_matchpatch" "$(awk "BEGIN { print $t1 - $t0 }")" "$result" "$mask"
  done
done
cat "$table"
echo "images and table in $out/"
