#!/usr/bin/python3
"""Rate-quality plots from a vqtex-bench CSV: mean SWD and completeness against
bits per exemplar pixel, one line per codec, one figure per protocol.
Needs Debian's python3-matplotlib (hence /usr/bin/python3). Usage: bench/plot.py RESULTS.csv OUT_PREFIX"""
import csv
import sys
from collections import defaultdict

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main():
    rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["status"] == "ok"]
    prefix = sys.argv[2]
    for protocol in ("same", "large"):
        # codec -> rate key -> list of (bpp, swd, completeness)
        series = defaultdict(lambda: defaultdict(list))
        floors = []
        for r in rows:
            if r["protocol"] != protocol or r["codec"].startswith("ceiling"):
                continue
            key = r["quality"] if r["codec"].startswith(("vqtex", "jpeg", "webp", "avif", "jxl")) else r["setting"]
            series[r["codec"]][key].append((float(r["bpp_exemplar"]), float(r["swd"]), float(r["completeness"])))
            floors.append(float(r["swd_floor"]))
        if not series:
            continue
        fig, axes = plt.subplots(1, 2, figsize=(12, 5))
        for codec, points in sorted(series.items()):
            pts = sorted((sum(p[0] for p in v) / len(v), sum(p[1] for p in v) / len(v),
                          sum(p[2] for p in v) / len(v)) for v in points.values())
            style = "o-" if codec == "vqtex" else ("s--" if codec.endswith("+synth") else "x:")
            axes[0].plot([p[0] for p in pts], [p[1] for p in pts], style, label=codec)
            axes[1].plot([p[0] for p in pts], [p[2] for p in pts], style, label=codec)
        if floors:
            axes[0].axhline(sum(floors) / len(floors), color="grey", lw=0.8, label="floor (exemplar vs held-out)")
        axes[0].set_title(f"{protocol}: sliced Wasserstein vs held-out (lower is better)")
        axes[1].set_title(f"{protocol}: completeness vs held-out (lower is better)")
        for ax in axes:
            ax.set_xlabel("bits per exemplar pixel")
            ax.set_xscale("log")
            ax.grid(True, alpha=0.3)
        axes[0].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(f"{prefix}_{protocol}.png", dpi=110)
        print(f"wrote {prefix}_{protocol}.png")


if __name__ == "__main__":
    main()
