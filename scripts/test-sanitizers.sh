#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer,
# then the concurrency tests under ThreadSanitizer (clang-14). Any report
# fails the run (-fno-sanitize-recover=all, halt_on_error).
#   bash scripts/test-sanitizers.sh           # both
#   bash scripts/test-sanitizers.sh asan      # or only one: asan | tsan
# Env: VQTEX_ASAN_BUILD_DIR (default build-asan/), VQTEX_TSAN_BUILD_DIR
# (default build-tsan/).
# Suppressions (tests/sanitizers/*.supp) name third-party libraries only
# (OpenImageIO and what it loads), never vqtex code.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
which="${1:-all}"
jobs="$(nproc)"

"$root/scripts/setup.sh" clang-14 libclang-rt-14-dev llvm-14
export CC=clang-14 CXX=clang++-14
command -v llvm-symbolizer-14 >/dev/null && export ASAN_SYMBOLIZER_PATH="$(command -v llvm-symbolizer-14)"
supp="$root/tests/sanitizers"
# Line tables are enough for symbolised reports and build faster than -g.
flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only"
       "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only" -DVQTEX_BUILD_BENCH=OFF)

if [ "$which" = all ] || [ "$which" = asan ]; then
  build="${VQTEX_ASAN_BUILD_DIR:-$root/build-asan}"
  echo "sanitizers: ASan+UBSan build in $build"
  cmake -S "$root" -B "$build" "${flags[@]}" -DVQTEX_SANITIZE=address,undefined >/dev/null
  cmake --build "$build" -j "$jobs"
  # intercept_tls_get_addr=0: the programs dlopen OpenImageIO (through
  # vqtex_imageio.so), whose libraries then keep dynamic TLS; clang-14's
  # leak checker misreads glibc 2.36's dynamic TLS blocks and its tracer
  # crashes at exit ("Tracer caught signal 11", google/sanitizers#1322).
  # Static TLS and every heap block are still scanned.
  export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:intercept_tls_get_addr=0"
  export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  # install_and_build_example is left out: it links examples/asset_packer.c
  # with the system C compiler, which cannot link a sanitized static
  # library; it tests packaging, and the API calls it makes are covered by
  # test_codec and test_api.
  # The tests that start the programs run apart: the programs read images
  # with OpenImageIO, whose one known leak (lsan.supp) LeakSanitizer
  # recognises only from a whole allocation stack, and the fast unwinder
  # stops in libstdc++ before reaching it.
  tools='^(FillTool|HostileImages|NothingLost|Tools|ToolsBatch|ToolsMaps)\.'
  (cd "$build" && ctest --output-on-failure -j "$jobs" -E "^install_and_build_example\$|$tools")
  (cd "$build" && ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0" ctest --output-on-failure -j "$jobs" -R "$tools")
fi

if [ "$which" = all ] || [ "$which" = tsan ]; then
  build="${VQTEX_TSAN_BUILD_DIR:-$root/build-tsan}"
  echo "sanitizers: TSan build in $build (concurrency tests)"
  cmake -S "$root" -B "$build" "${flags[@]}" -DVQTEX_SANITIZE=thread >/dev/null
  cmake --build "$build" -j "$jobs" --target test_concurrency test_codec test_synthesis test_tsvq test_api test_material
  export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$supp/tsan.supp"
  # Every test that runs threads: the concurrency suite, and the
  # same-bytes-for-any-thread-count tests of the other suites.
  (cd "$build" && ctest --output-on-failure -j "$jobs" -R 'Concurren|ThreadCount|AnyThread|Threads')
fi
