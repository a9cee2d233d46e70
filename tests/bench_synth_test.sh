#!/usr/bin/env bash
# Runs vqtex-bench's synth protocol on two textures of the project corpus,
# twice with one G'MIC cache, and checks the CSV: a scored vqtex row per
# texture, a G'MIC row that is scored or says 'missing' (gmic is optional),
# the second run served from the cache with the same scores, and one
# contact sheet per texture. Usage: bench_synth_test.sh BENCH CORPUS
set -euo pipefail
bench="$1"
corpus="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
for run in 1 2; do
    "$bench" "$corpus" --protocols synth --limit 2 --synth-cache "$tmp/cache" --sheets "$tmp/sheets" \
        --csv "$tmp/run$run.csv" > "$tmp/summary$run.txt" 2> "$tmp/log$run.txt"
done
grep -q "^synth protocol" "$tmp/summary1.txt"
python3 - "$tmp" <<'PY'
import csv, math, os, sys
tmp = sys.argv[1]
runs = [list(csv.DictReader(open(f"{tmp}/run{i}.csv"))) for i in (1, 2)]
rows = runs[0]
assert {r["protocol"] for r in rows} == {"synth"}, "only synth rows expected"
textures = sorted({r["texture"] for r in rows})
assert len(textures) == 2, textures
scores = ("swd", "colour_dist", "completeness", "coherence", "copy_exact", "seam_ratio", "straight_seam")
def scored(r):
    for k in scores:
        v = float(r[k])
        assert math.isfinite(v) and v >= 0, (k, r)
    assert 0 < float(r["swd"]) < 100, r
for t in textures:
    v = [r for r in rows if r["texture"] == t and r["codec"] == "vqtex"]
    assert len(v) == 1 and v[0]["status"] == "ok", v
    scored(v[0])
    g = [r for r in rows if r["texture"] == t and r["codec"] == "gmic"]
    assert len(g) == 1 and g[0]["status"] in ("ok", "missing"), g
    if g[0]["status"] == "ok":
        scored(g[0])
        again = [r for r in runs[1] if r["texture"] == t and r["codec"] == "gmic"][0]
        assert again["setting"].endswith(" cached"), again
        assert all(again[k] == g[0][k] for k in scores), (again, g[0])
    stem = os.path.splitext(t)[0]
    assert os.path.getsize(f"{tmp}/sheets/synth_{stem}.png") > 0, stem
print(f"bench synth: {len(rows)} rows OK")
PY
