#!/usr/bin/env bash
# Runs vqtex-bench's materials protocol on one set of the shared corpus
# (brick, reduced to 128x128, the default quality and one byte target) and
# checks the CSV: a scored row per rate, mode and map, the pair rows, the
# normal map's shading, the set's shares adding up to its file, each map
# alone within its share, the set's maps aligned (their luminance
# correlations near the example's, nearer than the maps stored alone), and
# the contact sheets. Skipped (77) without the shared corpus.
# Usage: bench_materials_test.sh BENCH MATERIALS
set -euo pipefail
bench="$1"
materials="$2"
if [ ! -f "$materials/brick/albedo.png" ]; then
    echo "bench materials: no $materials/brick: skipped"
    exit 77
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$bench" "$materials" --protocols materials --sets brick --material-side 128 --target-sizes 8000 \
    --csv "$tmp/materials.csv" --sheets "$tmp/sheets" > "$tmp/summary.txt" 2> "$tmp/log.txt"
grep -q "^materials protocol (1 sets; maps 128x128 decoded at 128x128" "$tmp/summary.txt"
python3 - "$tmp" <<'PY'
import csv, math, os, re, sys
tmp = sys.argv[1]
rows = list(csv.DictReader(open(f"{tmp}/materials.csv")))
assert {r["set"] for r in rows} == {"brick"} and {r["protocol"] for r in rows} == {"materials"}, rows[:1]
maps = {"albedo": "colour", "normal": "normal", "gloss": "data"}
pairs = ("albedo~normal", "albedo~gloss", "normal~gloss")
rates = (("50", "0"), ("-1", "8000"))
def get(rate, mode, m):
    got = [r for r in rows if (r["quality"], r["target_size"]) == rate and r["mode"] == mode and r["map"] == m]
    assert len(got) == 1, (rate, mode, m, len(got))
    return got[0]
# A map the set predicts from another (the gloss, from the albedo) may take
# fewer bytes than any file of one map: its row alone is then "no-fit", and
# the pairs alone that hold it are not scored.
def unfit(rate, m):
    got = [r for r in rows if (r["quality"], r["target_size"]) == rate and r["mode"] == "separate" and r["map"] == m]
    return len(got) == 1 and got[0]["status"] == "no-fit"
missing = sum(1 for rate in rates for p in pairs if any(unfit(rate, m) for m in p.split("~")))
assert len(rows) == len(rates) * 2 * (len(maps) + len(pairs)) - missing, (len(rows), missing)
diffs = {"set": [], "separate": []}
for rate in rates:
    for mode in ("set", "separate"):
        for m, kind in maps.items():
            r = get(rate, mode, m)
            if mode == "separate" and unfit(rate, m):
                assert int(get(rate, "set", m)["bytes"]) < 256, ("a map that fits no file alone is a predicted one", r)
                continue
            assert r["status"] == "ok" and r["kind"] == kind, r
            assert r["side"] == "128" and r["output_side"] == "128", r
            for k in ("swd", "completeness", "coherence", "coherence_half", "seam_visibility"):
                assert r[k] != "" and math.isfinite(float(r[k])) and float(r[k]) >= 0, (k, r)
            assert 0 < float(r["swd"]) < 100, r
            shaded = [r[k] for k in ("nl_mean", "nl_sd", "nl_wasserstein", "off_unit")]
            if kind == "normal":
                assert all(v != "" for v in shaded), r
                assert 0 < float(r["nl_mean"]) <= 1 and float(r["nl_wasserstein"]) < 0.1, r
                assert float(r["off_unit"]) < 0.01, f"decoded normals off unit length: {r}"
            else:
                assert all(v == "" for v in shaded), r
            assert r["corr"] == "", r
        for p in pairs:
            if mode == "separate" and any(unfit(rate, m) for m in p.split("~")):
                continue
            r = get(rate, mode, p)
            assert r["kind"] == "pair" and r["swd"] == "", r
            corr, example = float(r["corr"]), float(r["corr_example"])
            assert -1 <= corr <= 1 and abs(float(r["corr_diff"]) - (corr - example)) < 1e-3, r
            diffs[mode].append(abs(corr - example))
    # The set's shares add up to its file; each map alone fits its share.
    s = [get(rate, "set", m) for m in maps]
    assert sum(int(r["bytes"]) for r in s) == int(s[0]["file_bytes"]) > 100, s
    for m in maps:
        if unfit(rate, m):
            continue
        share = int(get(rate, "set", m)["bytes"])
        alone = get(rate, "separate", m)
        assert re.match(rf"--target-size {share} ", alone["setting"]), alone
        assert 0 < int(alone["bytes"]) <= share and alone["bytes"] == alone["file_bytes"], (share, alone)
mean = {k: sum(v) / len(v) for k, v in diffs.items()}
assert mean["set"] < 0.1 and mean["set"] < mean["separate"], f"set maps not aligned: {mean}"
for name in ("q50", "t8000"):
    assert os.path.getsize(f"{tmp}/sheets/materials_brick_{name}.png") > 0, name
print(f"bench materials: {len(rows)} rows OK (mean |corr diff| set {mean['set']:.3f}, separate {mean['separate']:.3f})")
PY
