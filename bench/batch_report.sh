#!/usr/bin/env bash
# batch_report.sh - the figures of docs/PERFORMANCE.md "Start-up, batches and
# writing": the programs' start-up, a 100-file vqtex-decode batch against
# the library decode plus PNG write of one file, and PNG write time per zlib
# level at 512 and 2048. Uses hyperfine when installed (a measuring tool,
# not a dependency: apt-get install hyperfine), else a shell loop.
# Usage: bench/batch_report.sh BUILD_DIR CORPUS_DIR [JOBS]
set -euo pipefail
build="$(cd "$1" && pwd)"
corpus="$2"
jobs="${3:-2}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Median wall time in ms of a command run N times (the first run is a warm-up).
median_ms() {
  local n="$1"; shift
  "$@" >/dev/null 2>&1 || true
  for _ in $(seq "$n"); do
    local t0 t1
    t0=$(date +%s%N); "$@" >/dev/null 2>&1 || true; t1=$(date +%s%N)
    echo $(((t1 - t0) / 1000))
  done | sort -n | awk '{a[NR]=$1} END {printf "%.1f", a[int((NR+1)/2)]/1000}'
}

"$build/vqtex-encode" "$corpus/bricks_128.png" "$tmp/bricks.vqt" --quiet
echo "## start-up (median of 20, ms)"
for cmd in "vqtex-info $tmp/bricks.vqt" "vqtex-info --help" "vqtex-decode --size" \
           "vqtex-decode $tmp/bricks.vqt $tmp/one.png --size 512x512 -j $jobs"; do
  printf '%-70s %8s\n' "$cmd" "$(median_ms 20 "$build"/$cmd)"
done

echo "## 100 files of 128x128 to 512x512 PNG, -j $jobs"
mkdir -p "$tmp/in" "$tmp/out"
i=0
for f in "$corpus"/*_128.png; do
  "$build/vqtex-encode" "$f" "$tmp/in/$(basename "$f" .png).vqt" --quiet
  i=$((i + 1))
  [ "$i" -ge 5 ] && break
done
n=0
while [ "$n" -lt 100 ]; do
  for f in "$tmp"/in/*.vqt; do
    [ "$n" -lt 100 ] && cp "$f" "$tmp/in/$(printf 'f%03d' "$n")_$(basename "$f")"
    n=$((n + 1))
  done
done
find "$tmp/in" -maxdepth 1 -name '*.vqt' ! -name 'f[0-9][0-9][0-9]_*' -delete
t0=$(date +%s%N)
"$build/vqtex-decode" "$tmp/in" -o "$tmp/out" --size 512x512 -j "$jobs" --quiet
t1=$(date +%s%N)
batch_ms=$(((t1 - t0) / 1000000))
# The library decode plus the PNG write of each file, measured inside one
# call per file (without the start-up: the program loads OpenImageIO before
# it starts the write's clock and reports the load apart), and the same
# bytes as the batch.
lib_ms=0
load_ms=0
t0=$(date +%s%N)
for f in "$tmp"/in/*.vqt; do
  out="$tmp/single_$(basename "$f" .vqt).png"
  j=$("$build/vqtex-decode" "$f" "$out" --size 512x512 -j "$jobs" --json)
  read -r ms lms < <(echo "$j" | python3 -c 'import json,sys; d=json.load(sys.stdin); print(int(1000*(d["decode_seconds"]+d["write_seconds"])), int(1000*d["image_io_load_seconds"]))')
  lib_ms=$((lib_ms + ms))
  load_ms=$((load_ms + lms))
  cmp -s "$out" "$tmp/out/$(basename "$f" .vqt).png" || { echo "batch output differs for $f" >&2; exit 1; }
done
t1=$(date +%s%N)
singles_ms=$(((t1 - t0) / 1000000))
awk -v b="$batch_ms" -v l="$lib_ms" -v s="$singles_ms" -v o="$load_ms" 'BEGIN {
  printf "one batch call:                      %6d ms, %6.1f ms per file\n", b, b / 100
  printf "library decode + PNG write, summed:  %6d ms, %6.1f ms per file (inside 100 single calls)\n", l, l / 100
  printf "OpenImageIO load, summed:            %6d ms, %6.1f ms per file (inside 100 single calls)\n", o, o / 100
  printf "100 single calls:                    %6d ms, %6.1f ms per file\n", s, s / 100
  printf "batch per file / (decode + write):   %.2f\n", b / l
}'
echo "same bytes as the 100 single calls: yes"

echo "## PNG write time per zlib level (one call each; OpenImageIO's load not counted)"
for size in 512 2048; do
  for level in 0 1 3 6 9; do
    j=$("$build/vqtex-decode" "$tmp/bricks.vqt" "$tmp/w.png" --size "$size" -j "$jobs" --png-compression "$level" --json)
    echo "$j" | python3 -c "import json,sys,os; d=json.load(sys.stdin); print('$size level $level: decode %.3f s, write %.3f s, %d bytes (OpenImageIO load %.3f s)' % (d['decode_seconds'], d['write_seconds'], os.path.getsize('$tmp/w.png'), d['image_io_load_seconds']))"
  done
done
