#!/usr/bin/python3
"""Rate-quality plots from a vqtex-bench CSV (written with --csv).

PREFIX_same.png, PREFIX_large.png: mean SWD and completeness against bits
per exemplar pixel, one line per codec (vqtex, each peer's decode, each
peer + vqtex synthesis), one figure per protocol.

PREFIX_large_synthesis.png (the acceptance test's rows): mean completeness,
SWD and coherence against the file's bytes for the large protocol's synthesis rows: vqtex,
each PEER+synth (vqtex's engine), each PEER+gmic (G'MIC), with the ceilings
(synthesis from the lossless exemplar) and the floor (the exemplar itself
against the held-out crop) as horizontal lines.

Every point is a mean over the textures that row scored; a peer that does
not fit a budget on some textures is averaged over fewer of them, which the
legend marks with "(fewer textures)".

Needs matplotlib: Debian's python3-matplotlib (scripts/setup-bench.sh
installs it), hence /usr/bin/python3 in the first line.
Usage: bench/plot.py RESULTS.csv OUT_PREFIX"""
import csv
import sys
from collections import defaultdict

try:
    import matplotlib
except ImportError:
    sys.exit("plot.py: error: matplotlib is missing for " + sys.executable + ". On Debian: "
             "'apt-get install python3-matplotlib' (or scripts/setup-bench.sh), then run this script "
             "as bench/plot.py or with /usr/bin/python3; with another Python: 'pip install matplotlib'.")
matplotlib.use("Agg")
import matplotlib.pyplot as plt

# The large protocol's synthesis figure: (CSV column, title) per panel.
SYNTHESIS_METRICS = (("completeness", "completeness"), ("swd", "sliced Wasserstein (SWD)"),
                     ("coherence", "coherence"))


def mean(values):
    return sum(values) / len(values)


def codec_figures(rows, prefix):
    """The figures per protocol, against bits per exemplar pixel."""
    for protocol in ("same", "large"):
        # codec -> rate key -> list of (bpp, swd, completeness)
        series = defaultdict(lambda: defaultdict(list))
        floors = []
        for r in rows:
            # G'MIC's rows have their own figure (synthesis_figure).
            if r["protocol"] != protocol or r["codec"].startswith("ceiling") or r["codec"].endswith("+gmic"):
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
            style = "o-" if codec.startswith("vqtex") else ("s--" if codec.endswith("+synth") else "x:")
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


def synthesis_figure(rows, prefix):
    """The large protocol's synthesis rows against bytes (the acceptance test's)."""
    large = [r for r in rows if r["protocol"] == "large"]
    # codec -> rate (the quality column: a -q preset or a byte target) -> rows
    curves = defaultdict(lambda: defaultdict(list))
    ceilings = defaultdict(list)  # ceiling codec -> rows
    floor_rows = {}  # texture -> a row (every row of a texture holds its floor)
    for r in large:
        codec = r["codec"]
        floor_rows.setdefault(r["texture"], r)
        if codec.startswith("ceiling:"):
            ceilings[codec].append(r)
        elif codec.startswith("vqtex") or codec.endswith(("+synth", "+gmic")):
            curves[codec][r["quality"]].append(r)
    if not curves:
        return
    textures = len(floor_rows)
    peers = sorted({c.rsplit("+", 1)[0] for c in curves if not c.startswith("vqtex")})
    colours = {peer: f"C{i}" for i, peer in enumerate(peers)}
    fig, axes = plt.subplots(1, len(SYNTHESIS_METRICS), figsize=(17, 5.5))
    for ax, (column, title) in zip(axes, SYNTHESIS_METRICS):
        for codec in sorted(curves, key=lambda c: (not c.startswith("vqtex"), c.endswith("+gmic"), c)):
            points = sorted((mean([float(r["bytes"]) for r in v]), mean([float(r[column]) for r in v]), len(v))
                            for v in curves[codec].values())
            fewer = " (fewer textures)" if any(n < textures for _, _, n in points) else ""
            if codec.startswith("vqtex"):
                style = dict(color="black", marker="o", ls="-", lw=2)
            else:
                peer, synthesiser = codec.rsplit("+", 1)
                style = dict(color=colours[peer], marker="s" if synthesiser == "synth" else "^",
                             ls="-" if synthesiser == "synth" else "--", lw=1)
            ax.plot([p[0] for p in points], [p[1] for p in points], label=codec + fewer, **style)
        for codec, v in sorted(ceilings.items()):
            ls = "-" if "synth" in codec else "--"
            ax.axhline(mean([float(r[column]) for r in v]), color="grey", ls=ls, lw=1,
                       label=codec.replace("ceiling:", "ceiling: "))
        ax.axhline(mean([float(r[column + "_floor"]) for r in floor_rows.values()]), color="lightgrey", ls=":",
                   lw=1, label="floor: exemplar vs held-out")
        ax.set_title(f"large: {title} (lower is better)")
        ax.set_xlabel("bytes")
        ax.set_xscale("log", base=2)
        ax.grid(True, alpha=0.3)
    # One legend for the three panels, under them, where it hides no curve.
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=5, fontsize=8)
    fig.suptitle(f"vqtex against peer + synthesis, {textures} textures (means over the textures each row scored)")
    fig.tight_layout(rect=(0, 0.05 + 0.025 * ((len(labels) + 4) // 5), 1, 1))
    fig.savefig(f"{prefix}_large_synthesis.png", dpi=110)
    print(f"wrote {prefix}_large_synthesis.png")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["status"] == "ok"]
    prefix = sys.argv[2]
    codec_figures(rows, prefix)
    synthesis_figure(rows, prefix)


if __name__ == "__main__":
    main()
