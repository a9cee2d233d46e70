#!/usr/bin/env bash
# Installs the built project into a temporary prefix, then builds and runs
# examples/asset_packer.c against it twice: through find_package(vqtex) and
# through pkg-config. Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$1"
src="$2"
prefix="$(mktemp -d)"
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" >/dev/null
# Benchmark programs stay in the build tree.
for program in vqtex-bench fill-seams; do
  if [ -e "$prefix/bin/$program" ]; then
    echo "install test: $program was installed into bin" >&2
    exit 1
  fi
done

# The installed programs load the installed image I/O module (LIBDIR/vqtex),
# not the build tree's, and write an image with it.
if [ -x "$prefix/bin/vqtex-decode" ]; then
  LD_DEBUG=files "$prefix/bin/vqtex-decode" "$src/tests/golden/cellular_v1.vqt" "$prefix/out.png" --size 40x24 \
    --quiet 2>"$prefix/ld.log"
  if ! grep -q "file=$prefix/lib[^ ]*/vqtex/vqtex_imageio.so" "$prefix/ld.log"; then
    echo "install test: vqtex-decode did not load $prefix's vqtex_imageio.so" >&2
    exit 1
  fi
  [ -s "$prefix/out.png" ] || { echo "install test: the installed vqtex-decode wrote no image" >&2; exit 1; }
fi

cmake -S "$src/examples" -B "$prefix/examples-build" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$prefix/examples-build" >/dev/null
"$prefix/examples-build/asset_packer"

export PKG_CONFIG_PATH="$prefix/lib/pkgconfig:$prefix/lib/x86_64-linux-gnu/pkgconfig:${PKG_CONFIG_PATH:-}"
# shellcheck disable=SC2046
cc -std=c99 -Wall -Werror "$src/examples/asset_packer.c" -o "$prefix/asset_packer_pc" $(pkg-config --cflags --libs --static vqtex)
# A shared build's library is found where it was installed (pkg-config
# gives no run path).
LD_LIBRARY_PATH="$prefix/lib:$prefix/lib/x86_64-linux-gnu:${LD_LIBRARY_PATH:-}" "$prefix/asset_packer_pc" >/dev/null
echo "install test: find_package and pkg-config builds both ran"
