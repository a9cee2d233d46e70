#!/usr/bin/env bash
# decode_memory.sh - peak memory of decoding atlas files (format v7, what
# `vqtex-encode --atlas` writes; v3 to v6 decode the same way with no more:
# no edge guard, before v6 no copy relocation, before v5 no blend at seams)
# against the decoder's budget (docs/PERFORMANCE.md "Memory"): at most
# twice the output (W x H x channels bytes) plus 16 MB.
#
#   bash bench/decode_memory.sh [BUILD_DIR] [SIDES] [THREADS]
#
# Defaults: build/, sides "512 2048 4096", threads "1 2". Four files, made
# with `vqtex-encode --atlas`: corpus/cellular_128.png (3 channels,
# --target-size 4000), corpus/grey_noise_64.png (1 channel),
# corpus/leaves_rgba_64.png (4 channels) and corpus/sand_256.png at -q 100
# (a 256x256 atlas, whose analysis is made level by level). Two figures
# per size:
#   library  - what one vqtex_decode call adds to the resident set, in a
#              fresh process (bench_scaling --memory-child: its high-water
#              mark, getrusage ru_maxrss, less the resident set just before
#              the call), i.e. what the budget is about;
#   command  - the whole peak of `vqtex-decode FILE OUT.png --size WxH`
#              (/usr/bin/time %M), libraries, file reading and the PNG
#              writer included, for reference.
# Prints a Markdown table (MiB; 1 MiB = 1024 KiB); exits 1 if any library
# figure is over its budget.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
sides="${2:-512 2048 4096}"
threads_list="${3:-1 2}"
for tool in "$build/bench/bench_scaling" "$build/vqtex-encode" "$build/vqtex-decode"; do
    [[ -x "$tool" ]] || { echo "decode_memory: $tool is missing: build with benchmarks (scripts/build.sh)" >&2; exit 1; }
done
[[ -x /usr/bin/time ]] || { echo "decode_memory: /usr/bin/time is missing (apt-get install time)" >&2; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
mib() { awk -v k="$1" 'BEGIN {printf "%.1f", k / 1024}'; }

# example, channels, encoder options
examples=("cellular_128.png 3 --target-size 4000" "grey_noise_64.png 1" "leaves_rgba_64.png 4" "sand_256.png 3 -q 100")
for example in "${examples[@]}"; do
    read -r name channels options <<<"$example"
    # shellcheck disable=SC2086 # options are words
    "$build/vqtex-encode" "$root/corpus/$name" "$tmp/${name%.png}.vqt" --atlas $options --quiet
    echo "- corpus/$name: --atlas ${options:-(defaults)}, $(stat -c %s "$tmp/${name%.png}.vqt") bytes, channels: $channels."
done
echo
echo "| file | output | threads | output MiB | budget MiB (2x + 16) | library peak MiB | within | command peak MiB |"
echo "|---|---|---|---|---|---|---|---|"
status=0
for example in "${examples[@]}"; do
    read -r name channels _ <<<"$example"
    file="$tmp/${name%.png}.vqt"
    for side in $sides; do
        for threads in $threads_list; do
            output_kib=$((side * side * channels / 1024))
            budget_kib=$((2 * output_kib + 16 * 1024))
            library_kib="$("$build/bench/bench_scaling" --memory-child "$file" --sizes "$side" -j "$threads")"
            command_kib="$(/usr/bin/time -f '%M' "$build/vqtex-decode" "$file" "$tmp/out.png" --size "${side}x${side}" \
                -j "$threads" --quiet 2>&1 >/dev/null | tail -1)"
            within=yes
            if ((library_kib > budget_kib)); then
                within=NO
                status=1
            fi
            echo "| ${name%.png} | ${side}x${side} | $threads | $(mib "$output_kib") | $(mib "$budget_kib") |" \
                 "$(mib "$library_kib") | $within | $(mib "$command_kib") |"
        done
    done
done
exit "$status"
