#!/usr/bin/python3
"""The synth protocol of vqtex-bench over several seeds: an engine change
judged on means with less noise than one seed gives (as in
docs/studies/2026-11-24-copy-relocation.md).

One synthesis is one random sample of the texture, and per texture the
scores move with the seed by more than most engine changes move them
(docs/studies/2026-11-24-atlas-choice-per-texture.md "The counts are
mostly noise"). The synth protocol is fast
(about 7 s for the 23 photographs at 256x256), so three seeds cost little.
This runs it once per seed into OUT/sSEED.csv (kept: a second call with the
same OUT only reads them), then prints each row's mean completeness, SWD
and coherence over the seeds and textures; with --against, the same for an
earlier OUT and the per-texture changes. G'MIC's rows need its outputs for
that seed in --synth-cache (or gmic on PATH); without them they are left
out.

Usage: bench/synth_seeds.py OUT [--bench build/vqtex-bench]
           [--corpus ../shared/corpus] [--pattern _256.png] [--seeds 1,2,3]
           [--synth-cache DIR] [--against EARLIER_OUT]
"""
import argparse
import csv
import os
import subprocess
import sys

METRICS = (("compl", "completeness"), ("SWD", "swd"), ("coher", "coherence"))


def run_seeds(args, out):
    os.makedirs(out, exist_ok=True)
    for seed in args.seeds:
        path = os.path.join(out, f"s{seed}.csv")
        if os.path.exists(path):
            continue
        command = [args.bench, args.corpus, "--pattern", args.pattern, "--protocols", "synth", "--seed", str(seed),
                   "--csv", path + ".part"]
        if args.synth_cache:
            command += ["--synth-cache", args.synth_cache]
        with open(os.path.join(out, f"s{seed}.log"), "w") as log:
            if subprocess.call(command, stdout=log, stderr=subprocess.STDOUT) != 0:
                sys.exit(f"synth_seeds: {' '.join(command)} failed; see {log.name}")
        os.replace(path + ".part", path)


def read(out, seeds):
    """codec -> texture -> mean (completeness, swd, coherence) over the seeds that scored it."""
    runs = {}
    for seed in seeds:
        path = os.path.join(out, f"s{seed}.csv")
        if not os.path.exists(path):
            sys.exit(f"synth_seeds: {path} is missing; run without --against first")
        for r in csv.DictReader(open(path)):
            if r["protocol"] != "synth" or r["status"] != "ok":
                continue
            runs.setdefault(r["codec"], {}).setdefault(r["texture"], []).append(
                tuple(float(r[column]) for _, column in METRICS))
    return {codec: {t: tuple(sum(s[m] for s in v) / len(v) for m in range(len(METRICS))) for t, v in textures.items()}
            for codec, textures in runs.items()}


def means(textures):
    n = len(textures)
    return tuple(sum(s[m] for s in textures.values()) / n for m in range(len(METRICS))), n


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--bench", default="build/vqtex-bench")
    ap.add_argument("--corpus", default="../shared/corpus")
    ap.add_argument("--pattern", default="_256.png")
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--synth-cache", default="")
    ap.add_argument("--against", default="")
    args = ap.parse_args()
    args.seeds = [int(s) for s in args.seeds.split(",") if s]
    run_seeds(args, args.out)
    rows = read(args.out, args.seeds)
    earlier = read(args.against, args.seeds) if args.against else {}
    print(f"synth protocol, seeds {','.join(map(str, args.seeds))}: means over textures (lower is better)")
    print(f"{'row':24s} {'n':>3s} " + " ".join(f"{name:>8s}" for name, _ in METRICS))
    for codec in sorted(rows):
        (scores, n) = means(rows[codec])
        line = f"{args.out + ':' + codec:24s} {n:3d} " + " ".join(f"{v:8.3f}" for v in scores)
        if codec in earlier:
            common = [t for t in rows[codec] if t in earlier[codec]]
            before = means({t: earlier[codec][t] for t in common})[0]
            after = means({t: rows[codec][t] for t in common})[0]
            line += "   change " + " ".join(f"{a - b:+7.3f}" for a, b in zip(after, before))
        print(line)
    if "vqtex" in rows and "vqtex" in earlier:
        print(f"\nper texture, vqtex: {args.against} -> {args.out}")
        for t in sorted(rows["vqtex"]):
            if t not in earlier["vqtex"]:
                continue
            b, a = earlier["vqtex"][t], rows["vqtex"][t]
            print(f"  {t[:28]:28s} " + "  ".join(f"{name} {x:6.2f} -> {y:6.2f}" for (name, _), x, y in zip(METRICS, b, a)))


if __name__ == "__main__":
    main()
