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
    # The large protocol's syntheses of each fitting peer's decode: vqtex's
    # engine (scored) and G'MIC (scored, or 'missing': gmic is optional).
    for r in rows:
        if r["texture"] != t or r["protocol"] != "large" or r["status"] != "ok" \
                or r["codec"] not in ("jpeg", "webp", "avif", "jxl"):
            continue
        for kind in ("+synth", "+gmic"):
            got = find(t, "large", r["codec"] + kind)
            assert len(got) == 1, f"{t} {r['codec']}{kind}: {len(got)} rows"
            assert got[0]["status"] in (("ok",) if kind == "+synth" else ("ok", "missing")), got[0]
            assert got[0]["bytes"] == r["bytes"], (got[0], r)
    g = find(t, "large", "ceiling:gmic-from-exemplar")
    assert len(g) == 1 and g[0]["status"] in ("ok", "missing"), g
print(f"bench quick: {len(rows)} rows OK")
PY
# The large protocol's summary ends with the acceptance test's comparison.
grep -q "^large protocol: vqtex against peer + synthesis" "$tmp/summary.txt"
grep -Eq "^  (compl|SWD|coher) .*(PASS|FAIL|n/a)" "$tmp/summary.txt"
