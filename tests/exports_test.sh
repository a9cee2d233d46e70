#!/usr/bin/env bash
# A shared build's libraries export the C API of vqtex.h and nothing else:
# the code is built with hidden visibility and linked with cmake/vqtex.map,
# which keeps local even the standard library's template instances. Lists
# each library's defined dynamic symbols and fails on any that is not
# vqtex_*. Usage: exports_test.sh LIBRARY.so...
set -euo pipefail
status=0
for lib in "$@"; do
  # Defined dynamic symbols: type letter, name (nm -D --defined-only).
  exported="$(nm -D --defined-only "$lib" | awk '{ print $(NF - 1), $NF }')"
  strays="$(printf '%s\n' "$exported" | awk '$2 !~ /^vqtex_/' || true)"
  internals="$(nm -DC --defined-only "$lib" | grep -E 'vqtex::' || true)"
  if [ -n "$strays" ] || [ -n "$internals" ]; then
    echo "exports: $lib exports more than the C API:" >&2
    printf '%s\n%s\n' "$strays" "$internals" | sed '/^$/d' | head -30 | sed 's/^/  /' >&2
    status=1
  else
    echo "exports: $lib: $(printf '%s\n' "$exported" | wc -l) symbols, all vqtex_*"
  fi
done
exit "$status"
