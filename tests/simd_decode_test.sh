#!/usr/bin/env bash
# Whole decodes under every kernel set: the golden still, animated and atlas files (atlas animations too),
# and a trees file encoded here (seam closing, several entries), decoded with
# VQTEX_SIMD forced to each level (dsp/dispatch.cpp takes the best available
# set not above it) must give the bytes of the default set. test_dsp checks
# the kernels one by one; this checks that nothing around them depends on
# the set. The set is chosen once per process, hence one process per set.
# The coherent engine (vqtex-synth, a still texture and an animation) is
# checked the same way: it calls the window-distance kernel.
# Usage: simd_decode_test.sh ENCODE_EXE DECODE_EXE GOLDEN_DIR CORPUS_DIR SYNTH_EXE
set -euo pipefail
encode="$1"
decode="$2"
golden="$3"
corpus="$4"
synth="$5"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

"$encode" "$corpus/leaves_rgba_64.png" "$work/leaves.vqt" -q 80 --trees --quiet

decode_all() {  # $1 = output directory
  mkdir -p "$1/anim"
  "$decode" "$golden/cellular_v1.vqt" "$1/cellular.png" --size 300x200 --seed 9 --quiet
  "$decode" "$work/leaves.vqt" "$1/leaves.png" --size 96x160 --mips --quiet
  "$decode" "$golden/flicker_v2.vqt" "$1/anim/f_%03d.png" --frames 10 --size 48x40 --seed 3 --quiet
  "$decode" "$golden/cellular_v3.vqt" "$1/atlas.png" --size 130x70 --seed 2 -j 2 --quiet
  "$decode" "$golden/cellular_v4.vqt" "$1/atlas_v4.png" --size 70x130 --seed 3 -j 2 --quiet
  "$decode" "$golden/cellular_v5.vqt" "$1/atlas_v5.png" --size 150x90 --seed 4 -j 2 --quiet
  "$decode" "$golden/cellular_v6.vqt" "$1/atlas_v6.png" --size 170x110 --seed 6 -j 2 --quiet
  "$decode" "$golden/cellular_v7.vqt" "$1/atlas_v7.png" --size 190x130 --seed 7 -j 2 --quiet
  "$decode" "$golden/cellular_v8.vqt" "$1/atlas_v8.png" --size 260x200 --seed 8 -j 2 --quiet
  "$decode" "$golden/material_v9.vqt" "$1/material_{map}.png" --size 180x120 --seed 9 -j 2 --quiet
  "$decode" "$golden/material_v17.vqt" "$1/material_v17_{map}.png" --size 170x130 --seed 17 -j 2 --quiet
  "$decode" "$golden/cellular_v10.vqt" "$1/atlas_v10.png" --size 280x210 --seed 10 -j 2 --quiet
  "$decode" "$golden/cellular_v15.vqt" "$1/atlas_v15.png" --size 300x220 --seed 15 -j 2 --quiet
  "$decode" "$golden/cellular_v19.vqt" "$1/atlas_v19.png" --size 310x230 --seed 19 -j 2 --quiet
  "$decode" "$golden/cellular_v20.vqt" "$1/atlas_v20.png" --size 330x250 --seed 20 -j 3 --quiet
  "$decode" "$golden/cellular_v21.vqt" "$1/atlas_v21.png" --size 330x250 --seed 21 -j 3 --quiet
  mkdir -p "$1/anim_v12"
  "$decode" "$golden/waves_v12.vqt" "$1/anim_v12/f_%03d.png" --frames 9 --size 70x60 --seed 11 -j 2 --quiet
  mkdir -p "$1/anim_v22"
  "$decode" "$golden/waves_v22.vqt" "$1/anim_v22/f_%03d.png" --frames 9 --size 70x60 --seed 22 -j 3 --quiet
  "$synth" "$corpus/cellular_128.png" "$1/coherent.png" --size 210x150 --seed 4 -j 2 --quiet
  mkdir -p "$1/anim_coherent"
  "$synth" "$corpus/flicker_32_anim/frame_%03d.png" "$1/anim_coherent/f_%03d.png" --frames 6 --size 40x36 --seed 2 -j 2 --quiet
}

decode_all "$work/default"
compared=0
for set in scalar sse2 avx2 avx512 avx512vnni; do
  VQTEX_SIMD="$set" decode_all "$work/$set"
  if ! diff -r "$work/default" "$work/$set" >/dev/null; then
    echo "decoding with VQTEX_SIMD=$set differs from the default kernel set" >&2
    exit 1
  fi
  compared=$((compared + 1))
done
files=$(find "$work/default" -type f | wc -l)
echo "simd decode test: $files output files identical under $compared forced kernel levels"
