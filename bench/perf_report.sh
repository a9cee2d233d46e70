#!/usr/bin/env bash
# perf_report.sh - the performance report of the codec (speed and memory
# targets, scaling with output size, and the comparison with G'MIC's
# patch-based synthesis). Writes OUT/perf.md plus the raw tables.
#
#   bash bench/perf_report.sh [CORPUS_DIR] [BUILD_DIR] [OUT_DIR]
#
# Needs a build with the benchmarks (bench_scaling) and tools, and gmic
# (scripts/setup-bench.sh). Textures: the 128x128 examples of the shared
# corpus named in $VQTEX_PERF_TEXTURES (default: five of them). Sections:
# $VQTEX_PERF_SECTIONS, any of "scaling gmic synth" (default "scaling gmic";
# the scaling runs take most of the time; synth times the coherent engine,
# vqtex_synthesize, against G'MIC). Times are wall clock, medians of
# $VQTEX_PERF_RUNS runs (default 5); run it on a quiet machine.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
corpus="${1:-$root/../shared/corpus}"
build="${2:-$root/build}"
out="${3:-$root/out/perf}"
textures="${VQTEX_PERF_TEXTURES:-stk_granite mate_grass ps_text tux_rocks stk_woodplanks}"
runs="${VQTEX_PERF_RUNS:-5}"
sections=" ${VQTEX_PERF_SECTIONS:-scaling gmic} "
mkdir -p "$out"
for tool in "$build/bench/bench_scaling" "$build/vqtex-encode" "$build/vqtex-decode"; do
    [[ -x "$tool" ]] || { echo "perf_report: $tool is missing: build with benchmarks (scripts/build.sh)" >&2; exit 1; }
done
have_gmic=1
command -v gmic >/dev/null || { have_gmic=0; echo "perf_report: gmic not found (bash scripts/setup-bench.sh); skipping the comparison" >&2; }

# Median of the arguments.
median_of() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

# Wall time of one run of a command, in seconds.
wall_time() {
    local start end
    start=$(date +%s.%N)
    "$@" >/dev/null 2>&1
    end=$(date +%s.%N)
    awk -v a="$start" -v b="$end" 'BEGIN {print b - a}'
}

# Median wall time of a command, in seconds.
median_time() {
    local times=() i
    for ((i = 0; i < runs; i++)); do times+=("$(wall_time "$@")"); done
    median_of "${times[@]}"
}

cores=$(nproc)
{
    echo "# vqtex performance report"
    echo
    echo "Machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs), $cores cores;" \
         "kernels: $(grep -o -w -E 'avx512_vnni|avx512bw|avx2' /proc/cpuinfo | sort -u | xargs)."
    echo "Date: $(date -u +%Y-%m-%d). Default settings (quality 50). Median of $runs runs."
    echo
} >"$out/perf.md"

first=1
[[ $sections == *" scaling "* ]] && for name in $textures; do
    example="$corpus/${name}_128.png"
    [[ -f "$example" ]] || { echo "perf_report: $example not found, skipped" >&2; continue; }
    for threads in 1 0; do
        label=$([[ $threads == 0 ]] && echo "all ($cores)" || echo 1)
        "$build/bench/bench_scaling" "$example" --sizes 128,256,512,1024,2048,4096 -j "$threads" \
            --runs "$runs" --tsv "$out/scaling_${name}_j${threads}.tsv" >"$out/scaling_${name}_j${threads}.txt"
        if [[ $first == 1 ]]; then
            {
                echo "## Scaling with output size: $name, threads $label"
                echo
                head -1 "$out/scaling_${name}_j${threads}.txt"
                echo
                echo "| side | decode s | Mpixel/s | ns/pixel | peak MB | budget MB (2x output + 16) |"
                echo "|---|---|---|---|---|---|"
                tail -n +2 "$out/scaling_${name}_j${threads}.tsv" |
                    awk -F'\t' '{printf "| %s | %.4f | %.2f | %.0f | %.1f | %.1f |\n", $1, $3, $4, $5, $6, $8}'
                echo
            } >>"$out/perf.md"
        fi
    done
    first=0
done

[[ $sections == *" scaling "* ]] && {
    echo "## Decode 512x512 and encode, per texture (library calls, no file I/O)"
    echo
    echo "| texture | encode 128 s (all cores) | decode 512 s, 1 thread | decode 512 s, all cores | decode 2048 s, all cores |"
    echo "|---|---|---|---|---|"
} >>"$out/perf.md"
[[ $sections == *" scaling "* ]] && for name in $textures; do
    [[ -f "$out/scaling_${name}_j1.tsv" ]] || continue
    enc=$(head -1 "$out/scaling_${name}_j0.txt" | sed -E 's/.*encode ([0-9.]+) s.*/\1/')
    d1=$(awk -F'\t' '$1==512 {print $3}' "$out/scaling_${name}_j1.tsv")
    d0=$(awk -F'\t' '$1==512 {print $3}' "$out/scaling_${name}_j0.tsv")
    d2048=$(awk -F'\t' '$1==2048 {print $3}' "$out/scaling_${name}_j0.tsv")
    echo "| $name | $enc | $d1 | $d0 | $d2048 |" >>"$out/perf.md"
done
echo >>"$out/perf.md"

if [[ $have_gmic == 1 && $sections == *" gmic "* ]]; then
    {
        echo "## Against G'MIC: 128x128 -> 512x512"
        echo
        echo "G'MIC: \`OMP_NUM_THREADS=1 gmic -v -1 IN syntexturize_matchpatch 512,512 o OUT.png\` (whole command)."
        echo "vqtex command: \`vqtex-decode FILE OUT.png --size 512x512\` (whole command: OpenImageIO start-up, decode, PNG write)."
        echo "Start-up of each program alone: \`gmic -v -1 IN o OUT.png\` and \`vqtex-info FILE\`."
        echo "vqtex library: \`vqtex_decode\` alone (bench_scaling, all cores, median of 3 in one process), what a program"
        echo "linking the library pays. Its runs alternate with G'MIC's, so both medians come from the same stretch of time;"
        echo "the last column is the ratio of each alternated pair (median, then lowest and highest), which cancels most"
        echo "of the machine's drift."
        echo
        echo "| texture | G'MIC s | G'MIC start-up s | vqtex-decode command s | vqtex start-up s | vqtex library s | command ratio | library ratio | per pair |"
        echo "|---|---|---|---|---|---|---|---|---|"
    } >>"$out/perf.md"
    for name in $textures; do
        example="$corpus/${name}_128.png"
        [[ -f "$example" ]] || continue
        file="$out/$name.vqt"
        "$build/vqtex-encode" "$example" "$file" >/dev/null
        # G'MIC and the library decode alternate run by run, so that both
        # medians come from the same stretch of time on a machine whose
        # speed drifts.
        gmic_times=() lib_times=() pair_ratios=()
        for ((i = 0; i < runs; i++)); do
            gmic_times+=("$(wall_time env OMP_NUM_THREADS=1 gmic -v -1 "$example" syntexturize_matchpatch 512,512 \
                o "$out/${name}_gmic_512.png")")
            "$build/bench/bench_scaling" "$example" --sizes 512 --runs 3 --tsv "$out/lib_512.tsv" >/dev/null
            lib_times+=("$(awk -F'\t' '$1==512 {print $3}' "$out/lib_512.tsv")")
            pair_ratios+=("$(awk -v a="${gmic_times[i]}" -v b="${lib_times[i]}" 'BEGIN {print a / b}')")
        done
        pairs=$(printf '%s\n' "${pair_ratios[@]}" | sort -g |
            awk '{a[NR]=$1} END {printf "%.1fx (%.1f-%.1f)", a[int((NR+1)/2)], a[1], a[NR]}')
        g=$(median_of "${gmic_times[@]}")
        lib=$(median_of "${lib_times[@]}")
        g0=$(median_time gmic -v -1 "$example" o "$out/${name}_gmic_noop.png")
        v=$(median_time "$build/vqtex-decode" "$file" "$out/${name}_vqtex_512.png" --size 512x512)
        v0=$(median_time "$build/vqtex-info" "$file")
        printf '| %s | %.3f | %.3f | %.3f | %.3f | %.4f | %.1fx | %.1fx | %s |\n' "$name" "$g" "$g0" "$v" "$v0" "$lib" \
            "$(awk -v a="$g" -v b="$v" 'BEGIN {print a / b}')" "$(awk -v a="$g" -v b="$lib" 'BEGIN {print a / b}')" \
            "$pairs" >>"$out/perf.md"
    done
    echo >>"$out/perf.md"
fi
if [[ $have_gmic == 1 && $sections == *" synth "* ]]; then
    {
        echo "## Coherent engine against G'MIC: 128x128 -> 512x512"
        echo
        echo "G'MIC: \`OMP_NUM_THREADS=1 gmic -v -1 IN syntexturize_matchpatch 512,512 o OUT.png\` (whole command)."
        echo "vqtex: \`vqtex_synthesize\` with default parameters (the coherent engine), all cores, median of 3"
        echo "in one process (\`bench_scaling IN --synth --sizes 512\`): the synthesis alone, and the analysis of the"
        echo "example (Gaussian stack, appearance vectors) alone. Runs alternate with G'MIC's; ratios per pair:"
        echo "median (lowest-highest)."
        echo
        echo "| texture | G'MIC s | vqtex synthesis s | vqtex analysis s | ratio, synthesis | ratio, analysis + synthesis |"
        echo "|---|---|---|---|---|---|"
    } >>"$out/perf.md"
    for name in $textures; do
        example="$corpus/${name}_128.png"
        [[ -f "$example" ]] || continue
        gmic_times=() synth_times=() analyse_times=() r1=() r2=()
        for ((i = 0; i < runs; i++)); do
            gmic_times+=("$(wall_time env OMP_NUM_THREADS=1 gmic -v -1 "$example" syntexturize_matchpatch 512,512 \
                o "$out/${name}_gmic_512.png")")
            "$build/bench/bench_scaling" "$example" --synth --sizes 512 --runs 3 --tsv "$out/synth_512.tsv" >/dev/null
            synth_times+=("$(awk -F'\t' '$1==512 {print $3}' "$out/synth_512.tsv")")
            analyse_times+=("$(awk -F'\t' '$1==512 {print $4}' "$out/synth_512.tsv")")
            r1+=("$(awk -v a="${gmic_times[i]}" -v b="${synth_times[i]}" 'BEGIN {print a / b}')")
            r2+=("$(awk -v a="${gmic_times[i]}" -v b="${synth_times[i]}" -v c="${analyse_times[i]}" 'BEGIN {print a / (b + c)}')")
        done
        summary() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END {printf "%.1fx (%.1f-%.1f)", a[int((NR+1)/2)], a[1], a[NR]}'; }
        printf '| %s | %.3f | %.4f | %.4f | %s | %s |\n' "$name" "$(median_of "${gmic_times[@]}")" \
            "$(median_of "${synth_times[@]}")" "$(median_of "${analyse_times[@]}")" "$(summary "${r1[@]}")" \
            "$(summary "${r2[@]}")" >>"$out/perf.md"
    done
    echo >>"$out/perf.md"
fi
cat "$out/perf.md"
