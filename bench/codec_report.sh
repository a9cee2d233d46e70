#!/usr/bin/env bash
# File sizes and encode/decode times of vqtex at three quality presets over a
# folder of textures, beside the same exemplar stored with WebP (cwebp -q 75)
# and JPEG (cjpeg -quality 75): the honest size bar. Prints a Markdown table.
#   bench/codec_report.sh [FOLDER] [BUILD_DIR]      (default ../shared/corpus, build)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
folder="${1:-$root/../shared/corpus}"
build="${2:-$root/build}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
qualities=(${VQTEX_QUALITIES:-25 50 75})
have() { command -v "$1" >/dev/null 2>&1; }
have cwebp || echo "note: cwebp missing (apt-get install webp): WebP column empty" >&2
have cjpeg || echo "note: cjpeg missing (apt-get install libjpeg-turbo-progs): JPEG column empty" >&2
have oiiotool || echo "note: oiiotool missing (apt-get install openimageio-tools): JPEG column empty" >&2

header="| texture | size |"
rule="|---|---|"
for q in "${qualities[@]}"; do header+=" q$q bytes | enc s | dec s |"; rule+="---|---|---|"; done
header+=" WebP q75 | JPEG q75 | PNG |"
rule+="---|---|---|"
echo "$header"
echo "$rule"
for f in "$folder"/*.png; do
  name="$(basename "$f" .png)"
  dims="$(python3 - "$f" <<'PY'
import struct, sys
with open(sys.argv[1], 'rb') as fh:
    head = fh.read(24)
print(f"{struct.unpack('>I', head[16:20])[0]}x{struct.unpack('>I', head[20:24])[0]}")
PY
)"
  w="${dims%x*}"
  row="| $name | $dims |"
  for q in "${qualities[@]}"; do
    enc="$("$build/vqtex-encode" "$f" "$tmp/x.vqt" -q "$q" --json -j 1)"
    bytes="$(echo "$enc" | python3 -c 'import json,sys; print(json.load(sys.stdin)["bytes"])')"
    es="$(echo "$enc" | python3 -c 'import json,sys; print("%.3f" % json.load(sys.stdin)["encode_seconds"])')"
    dec="$("$build/vqtex-decode" "$tmp/x.vqt" "$tmp/x.png" --size "$((2 * w))x$((2 * w))" --json -j 1)"
    ds="$(echo "$dec" | python3 -c 'import json,sys; print("%.3f" % json.load(sys.stdin)["decode_seconds"])')"
    row+=" $bytes | $es | $ds |"
  done
  webp=""; jpeg=""
  if have cwebp; then cwebp -quiet -q 75 "$f" -o "$tmp/x.webp" && webp="$(stat -c %s "$tmp/x.webp")"; fi
  # cjpeg 2.1 does not read PNG: go through PPM (grey images through PGM).
  if have cjpeg && have oiiotool; then
    oiiotool "$f" -o "$tmp/x.ppm" && cjpeg -quality 75 "$tmp/x.ppm" > "$tmp/x.jpg" && jpeg="$(stat -c %s "$tmp/x.jpg")"
  fi
  row+=" $webp | $jpeg | $(stat -c %s "$f") |"
  echo "$row"
done
