#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, AddressSanitizer + UndefinedBehavior-
# Sanitizer, fuzz/) and runs each for SECONDS (default 60) from a seed corpus
# made from corpus/ by fuzz/make_seeds. Fails on any crash, leak, timeout,
# sanitizer report or broken property; the input that broke it is kept in
# BUILD/fuzz-artifacts/. Found inputs accumulate in BUILD/fuzz-corpus/, so
# later runs start where earlier ones stopped.
#   bash scripts/fuzz.sh            # CI: about a minute per target
#   bash scripts/fuzz.sh 3600       # a long local run (see README)
# Env: VQTEX_FUZZ_BUILD_DIR (default build-fuzz/), VQTEX_FUZZ_TARGETS
# (default "fuzz_decode fuzz_inspect fuzz_encode"), VQTEX_FUZZ_ARGS (more
# libFuzzer flags, e.g. "-fork=2" to use two cores).
set -euo pipefail
seconds="${1:-60}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${VQTEX_FUZZ_BUILD_DIR:-$root/build-fuzz}"
targets=(${VQTEX_FUZZ_TARGETS:-fuzz_decode fuzz_inspect fuzz_encode})

"$root/scripts/setup.sh" clang-14 libclang-rt-14-dev llvm-14
export CC=clang-14 CXX=clang++-14
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVQTEX_FUZZ=ON \
  -DVQTEX_BUILD_TESTS=OFF -DVQTEX_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target "${targets[@]}" make_seeds

seeds="$build/fuzz-seeds"
rm -rf "$seeds"
"$build/fuzz/make_seeds" "$root/corpus" "$seeds"

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:symbolize=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
command -v llvm-symbolizer-14 >/dev/null && export ASAN_SYMBOLIZER_PATH="$(command -v llvm-symbolizer-14)"
mkdir -p "$build/fuzz-artifacts"
status=0
for t in "${targets[@]}"; do
  corpus="$build/fuzz-corpus/$t"
  mkdir -p "$corpus"
  case "$t" in
    fuzz_encode) seed_dir="$seeds/encode"; extra=() ;;
    *) seed_dir="$seeds/decode"; extra=(-dict="$root/fuzz/vqt.dict") ;;
  esac
  log="$build/fuzz-$t.log"
  echo "fuzz: $t for ${seconds}s (log $log)"
  # -timeout: one input taking over 10 s is a hang. -malloc_limit_mb: the
  # decoder's memory limit is 32 MiB in the targets, so any single
  # allocation of 256 MiB means a size field escaped it; -rss_limit_mb
  # bounds the whole process the same way.
  # shellcheck disable=SC2206
  extra+=(${VQTEX_FUZZ_ARGS:-})
  if "$build/fuzz/$t" "$corpus" "$seed_dir" "${extra[@]}" -max_total_time="$seconds" -timeout=10 \
      -malloc_limit_mb=256 -rss_limit_mb=1024 -print_final_stats=1 \
      -artifact_prefix="$build/fuzz-artifacts/$t-" >"$log" 2>&1; then
    grep -E "DONE|^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)" "$log" | sed "s/^/  /"
  else
    echo "fuzz: $t FAILED; the end of its log:" >&2
    tail -40 "$log" >&2
    status=1
  fi
done
exit "$status"
