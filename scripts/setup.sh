#!/usr/bin/env bash
# Installs what vqtex needs to build and test, from Debian packages, when it
# is missing, plus any packages named as arguments. Safe to run again: it
# installs nothing that is already there.
set -euo pipefail

packages=(
  build-essential cmake pkg-config python3
  libopenimageio-dev   # all image reading and writing
  libzstd-dev          # entropy coding of codebooks
  libdav1d-dev         # decoding the atlas of format v3 (AV1, exact by specification)
  libaom-dev           # encoding the atlas of format v3 (encoder library only)
  libwebp-dev          # bench/atlas_study.cpp: VP8 against AV1 for the atlas
  libcli11-dev         # command-line parsing
  nlohmann-json3-dev   # the programs' --json output
  libgtest-dev         # tests
  libbenchmark-dev     # benchmarks
)
# Extra packages a caller needs (scripts/test-sanitizers.sh, scripts/fuzz.sh).
packages+=("$@")

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "setup: installing ${missing[*]}" >&2
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
