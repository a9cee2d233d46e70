#!/usr/bin/env bash
# Runs vqtex-bench's animation protocol on the project corpus's animations
# only (no photographs), with one target and 8 output frames, and checks
# the CSV: every animation has its ceiling, vqtex and av1+synth rows, each
# scored or with a status saying why not, and the values are sane; and the
# summary is printed. Usage: bench_animation_test.sh BENCH CORPUS
set -euo pipefail
bench="$1"
corpus="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
"$bench" "$corpus" --protocols animation --shared '' --target-sizes 4000 --frames 8 \
  --csv "$tmp/anim.csv" > "$tmp/summary.txt" 2> "$tmp/log.txt"
python3 - "$tmp/anim.csv" "$corpus" <<'PY'
import csv, os, sys
rows = list(csv.DictReader(open(sys.argv[1])))
corpus = sys.argv[2]
expected = sorted(d for d in os.listdir(corpus) if d.endswith("_anim"))
animations = sorted({r["animation"] for r in rows})
assert animations == expected, f"animations {animations}, expected {expected}"
for a in animations:
    mine = [r for r in rows if r["animation"] == a]
    ceiling = [r for r in mine if r["codec"] == "ceiling"]
    assert len(ceiling) == 1 and ceiling[0]["status"] == "ok", ceiling
    for target in ("0", "4000"):
        v = [r for r in mine if r["codec"] == "vqtex" and r["target"] == target]
        assert len(v) == 1, f"{a} vqtex {target}: {len(v)} rows"
        v = v[0]
        assert v["status"] in ("ok", "limit-exceeded"), v
        if v["status"] != "ok":
            continue
        if target != "0":
            assert int(v["bytes"]) <= int(target), f"vqtex over its target: {v}"
        s = [r for r in mine if r["codec"] == "av1+synth" and r["target"] == target]
        assert len(s) == 1 and s[0]["status"] in ("ok", "no-fit"), s
        if s[0]["status"] == "ok":
            assert 0 < int(s[0]["bytes"]) <= int(v["bytes"]), f"av1+synth over the vqtex file's bytes: {s[0]}"
    for r in mine:
        if r["status"] != "ok":
            continue
        assert int(r["frames"]) == 8, r
        assert 0 < float(r["swd"]) < 100 and 0 < float(r["swd_floor"]) < 100, r
        assert 0 < float(r["coherence"]) < 100, r
        assert 0 <= float(r["seam_visibility"]) < 255, r
        # Outputs move (no frozen sequence), without flickering far above the example.
        assert 0.3 < float(r["change_ratio"]) < 3, r
        assert float(r["loop"]) > 0 and float(r["example_change"]) > 0, r
print(f"bench animation: {len(rows)} rows OK")
PY
grep -q "^animation protocol (means over output frames" "$tmp/summary.txt"
grep -Eq "^vqtex +4000 ok" "$tmp/summary.txt"
