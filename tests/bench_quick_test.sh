#!/usr/bin/env bash
# Runs `vqtex-bench --quick` on the project corpus and checks the CSV: the
# expected rows exist and the values are sane. Peers may be missing on the
# machine; their rows must then say so. Usage: bench_quick_test.sh BENCH CORPUS
set -euo pipefail
bench="$1"
corpus="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$bench" "$corpus" --quick --csv "$tmp/quick.csv" > "$tmp/summary.txt" 2> "$tmp/log.txt"
python3 - "$tmp/quick.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
textures = sorted({r["texture"] for r in rows})
assert len(textures) == 2, f"expected 2 textures, got {textures}"
def find(t, protocol, codec):
    return [r for r in rows if r["texture"] == t and r["protocol"] == protocol and r["codec"] == codec]
for t in textures:
    for protocol in ("same", "large"):
        for codec in ("vqtex", "ceiling:synth-from-exemplar"):
            got = find(t, protocol, codec)
            assert len(got) == 1, f"{t} {protocol} {codec}: {len(got)} rows"
            r = got[0]
            assert r["status"] == "ok", r
            swd, floor = float(r["swd"]), float(r["swd_floor"])
            assert 0 < swd < 100 and 0 <= floor < 100, r
            assert 0 <= float(r["copy_exact"]) <= 1, r
            assert 0 < float(r["seam_ratio"]) < 10, r
        v = find(t, protocol, "vqtex")[0]
        bytes_ = int(v["bytes"])
        assert bytes_ > 100, v
        scale = 1 if protocol == "same" else 4
        assert abs(float(v["bpp_exemplar"]) - scale * float(v["bpp_output"])) < 1e-3, v
    for codec in ("jpeg", "webp", "avif", "jxl"):
        got = [r for r in rows if r["texture"] == t and r["codec"] == codec]
        assert got, f"{t}: no {codec} row (neither a result nor 'missing')"
        for r in got:
            assert r["status"] in ("ok", "missing", "no-fit"), r
            if r["status"] == "ok":
                assert int(r["bytes"]) <= int(find(t, "same", "vqtex")[0]["bytes"]), f"{codec} over budget: {r}"
print(f"bench quick: {len(rows)} rows OK")
PY
