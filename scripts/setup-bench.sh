#!/usr/bin/env bash
# Installs the peer codecs and tools the benchmarks compare against (Debian
# packages). The benchmarks report a missing peer instead of failing, so
# this is optional.
set -euo pipefail
"$(dirname "${BASH_SOURCE[0]}")/setup.sh"
packages=(webp libjpeg-turbo-progs libavif-bin libjxl-tools astcenc openimageio-tools gmic python3-matplotlib time)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
sudo_cmd=()
[ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
