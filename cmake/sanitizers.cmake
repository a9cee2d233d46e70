# sanitizers.cmake - compile and link flags for the robustness builds:
# VQTEX_SANITIZE=address,undefined (the whole test suite, scripts/test-sanitizers.sh),
# VQTEX_SANITIZE=thread (the concurrency tests) and VQTEX_FUZZ (libFuzzer
# targets in fuzz/, scripts/fuzz.sh). Every target of the project gets the
# flags, so a report always points into instrumented code.
if(VQTEX_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "VQTEX_FUZZ needs clang's libFuzzer: configure with CC=clang-14 CXX=clang++-14")
  endif()
  if(NOT VQTEX_SANITIZE)
    set(VQTEX_SANITIZE "address,undefined")
  endif()
  # Coverage instrumentation everywhere; only the fuzz targets link the
  # libFuzzer driver (fuzz/CMakeLists.txt).
  add_compile_options(-fsanitize=fuzzer-no-link)
  # Numeric loops that give the fuzzer no feedback go uninstrumented for
  # coverage (the list says which and why): they were most of its time.
  add_compile_options(-fsanitize-coverage-ignorelist=${CMAKE_CURRENT_SOURCE_DIR}/fuzz/coverage_ignore.txt)
  # The appearance space's vector kernels go without UBSan's checks in this
  # build only (the list says why); ASan still checks them.
  add_compile_options(-fsanitize-ignorelist=${CMAKE_CURRENT_SOURCE_DIR}/fuzz/sanitizer_ignore.txt)
endif()
if(VQTEX_SANITIZE)
  message(STATUS "vqtex: building with -fsanitize=${VQTEX_SANITIZE}")
  # No recovery: the first report fails the test instead of scrolling by.
  add_compile_options(-fsanitize=${VQTEX_SANITIZE} -fno-sanitize-recover=all -fno-omit-frame-pointer -g)
  add_link_options(-fsanitize=${VQTEX_SANITIZE})
  # Lets tests shrink their slowest cases (never skip them).
  add_compile_definitions(VQTEX_SANITIZED=1)
endif()
