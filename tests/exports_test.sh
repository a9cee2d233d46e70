#!/usr/bin/env bash
# A shared build's libraries export the C API of vqtex.h only (VQTEX_API):
# every other symbol is built hidden. Lists each library's dynamic symbols
# and fails on any defined one that is not vqtex_*. Weak definitions of the
# C++ standard library's templates (V/W: std::, typeinfo of std::) that the
# compiler emits where they are used are not the library's; they are
# reported only if their name is vqtex's (vqtex::).
# Usage: exports_test.sh LIBRARY.so...
set -euo pipefail
status=0
for lib in "$@"; do
  # Defined dynamic symbols: type letter, name (nm -D --defined-only).
  exported="$(nm -D --defined-only "$lib" | awk '{ print $(NF - 1), $NF }')"
  strays="$(printf '%s\n' "$exported" | awk '$2 !~ /^vqtex_/' | grep -Ev '^[VWuv] ' || true)"
  internals="$(nm -DC --defined-only "$lib" | grep -E 'vqtex::' || true)"
  if [ -n "$strays" ] || [ -n "$internals" ]; then
    echo "exports: $lib exports more than the C API:" >&2
    printf '%s\n%s\n' "$strays" "$internals" | sed '/^$/d' | head -30 | sed 's/^/  /' >&2
    status=1
  else
    echo "exports: $lib: $(printf '%s\n' "$exported" | awk '$2 ~ /^vqtex_/' | wc -l) vqtex_* functions," \
         "$(printf '%s\n' "$exported" | awk '$2 !~ /^vqtex_/' | wc -l) weak standard-library symbols"
  fi
done
exit "$status"
