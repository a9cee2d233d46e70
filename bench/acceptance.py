#!/usr/bin/python3
"""The acceptance test (docs/ATLAS.md "How the textures compare") read over
several vqtex-bench runs that differ only in --seed
(docs/studies/2026-11-24-acceptance-two-seeds.md).

vqtex-bench's summary compares vqtex with the best PEER+synth row on one
decode per texture. A decode is one random sample of the texture: changing
the seed alone flips verdicts
(docs/studies/2026-11-24-atlas-choice-per-texture.md). The files do not
depend on the seed (the encoder and the peers' coders are deterministic), only the
synthesis does, so each texture's expected score is better estimated by
the mean over several seeds. This script takes one bench CSV per seed,
averages every (rate, row, texture)'s completeness, SWD and coherence over
the runs that scored it, and applies the bench's own rules
(print_large_summary in bench/vqtex_bench.cpp): per metric, the best peer
is the lowest mean among the PEER+synth rows that scored the most of
vqtex's textures; the verdict needs vqtex's mean at or below it and vqtex
at or below it on two thirds of the textures (rounded up). Given one CSV,
it prints the bench's own verdicts (a check of this script), up to the
CSV's four decimals: two scores that differ only beyond them tie here
(at or below) where the bench may not.

Under each rate it also applies the same test to the ceiling row (the
synthesis from the lossless exemplar) in vqtex's place: what a file that
decoded exactly as the exemplar does would score against the same peers.

Usage: bench/acceptance.py RUN.csv [RUN.csv ...] [--kind +synth|+gmic]
"""
import argparse
import collections
import csv

METRICS = (("compl", "completeness"), ("SWD", "swd"), ("coher", "coherence"))


def read_runs(paths):
    """rate -> codec -> texture -> [(completeness, swd, coherence) per run].

    Within one CSV a repeated row replaces the earlier one, as the bench's
    maps keep the last; across CSVs the runs are collected."""
    rows = collections.defaultdict(lambda: collections.defaultdict(lambda: collections.defaultdict(list)))
    ceilings = collections.defaultdict(lambda: collections.defaultdict(list))
    vqtex_codecs = set()
    for path in paths:
        run_rows, run_ceilings = {}, {}
        for r in csv.DictReader(open(path)):
            if r["protocol"] != "large" or r["status"] != "ok":
                continue
            scores = tuple(float(r[column]) for _, column in METRICS)
            if r["codec"].startswith("ceiling:"):
                run_ceilings[(r["codec"], r["texture"])] = scores
            elif r["codec"].startswith("vqtex") or r["codec"].endswith(("+synth", "+gmic")):
                run_rows[(int(r["quality"]), r["codec"], r["texture"])] = scores
                if r["codec"].startswith("vqtex"):
                    vqtex_codecs.add(r["codec"])
        for (codec, texture), scores in run_ceilings.items():
            ceilings[codec][texture].append(scores)
        for (rate, codec, texture), scores in run_rows.items():
            rows[rate][codec][texture].append(scores)
    if len(vqtex_codecs) > 1:
        raise SystemExit(f"acceptance: the runs hold several vqtex rows ({', '.join(sorted(vqtex_codecs))}); "
                         "give runs of one encoding (--atlas or not) only")
    return rows, ceilings


def averaged(textures):
    """texture -> mean scores over the runs that scored it."""
    return {t: tuple(sum(s[m] for s in runs) / len(runs) for m in range(len(METRICS)))
            for t, runs in textures.items()}


def pair_up(vqtex, peer, m):
    n = below = 0
    mine_sum = theirs_sum = 0.0
    for texture, scores in sorted(vqtex.items()):
        if texture not in peer:
            continue
        mine, theirs = scores[m], peer[texture][m]
        mine_sum += mine
        theirs_sum += theirs
        n += 1
        below += mine <= theirs
    return n, below, (mine_sum / n if n else 0.0), (theirs_sum / n if n else 0.0)


def best_peer(vqtex, peers, m):
    """The bench's test on metric m of vqtex (texture -> scores) against
    peers (codec -> texture -> scores): the best peer is the lowest mean
    among those that scored the most of vqtex's textures, taken in name
    order so that a tie on the mean goes to the first name, as in the
    bench's map. Returns (peer, n, at_or_below, vqtex_mean, peer_mean,
    needed, passes), or None without a peer."""
    names = sorted(peers)
    widest = max((pair_up(vqtex, peers[c], m)[0] for c in names), default=0)
    best = None
    for c in names:
        n, below, mine, theirs = pair_up(vqtex, peers[c], m)
        if n and n == widest and (best is None or theirs < best[4]):
            best = (c, n, below, mine, theirs)
    if best is None:
        return None
    c, n, below, mine, theirs = best
    needed = (2 * n + 2) // 3
    return c, n, below, mine, theirs, needed, mine <= theirs and below >= needed


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs", nargs="+", help="vqtex-bench --csv files, one per seed")
    ap.add_argument("--kind", default="+synth", help="peer rows to compare with (+synth: the acceptance)")
    args = ap.parse_args()
    rows, ceilings = read_runs(args.runs)
    runs_per_row = collections.Counter()
    print(f"{len(args.runs)} run(s); per texture, the mean over the runs that scored it; lower is better")
    print(f"{'rate':>6} {'metric':<6} {'vqtex':>7} {'best peer':>15} {'peer':>7} {'n':>3} "
          f"{'at/below':>8} {'needs':>5}  verdict")
    for rate in sorted(rows):
        codecs = {c: averaged(t) for c, t in rows[rate].items()}
        vqtex_codec = next((c for c in codecs if c.startswith("vqtex")), None)
        if vqtex_codec is None:
            continue
        for texture_runs in rows[rate][vqtex_codec].values():
            runs_per_row[len(texture_runs)] += 1
        peers = {c: t for c, t in codecs.items() if c.endswith(args.kind)}
        for m, (label, _) in enumerate(METRICS):
            result = best_peer(codecs[vqtex_codec], peers, m)
            if result is None:
                print(f"{rate:>6} {label:<6} no peer{args.kind} row")
                continue
            c, n, below, mine, theirs, needed, ok = result
            print(f"{rate:>6} {label:<6} {mine:7.2f} {c:>15} {theirs:7.2f} {n:3d} {below:8d} {needed:5d}  "
                  f"{'PASS' if ok else 'FAIL'}{'' if mine <= theirs else ' (mean above)'}")
        for name, textures in sorted(ceilings.items()):
            means = averaged(textures)
            line = " ".join(f"{sum(s[m] for s in means.values()) / len(means):.2f}" for m in range(len(METRICS)))
            print(f"{'':>6} {name} (over its {len(means)} textures): {line}")
            # The same test with the ceiling in vqtex's place: what a file
            # that decoded as the lossless exemplar does would score.
            # (docs/studies/2026-11-24-lossless-exemplar.md: it fails most
            # count tests.)
            verdicts = []
            for m, (label, _) in enumerate(METRICS):
                result = best_peer(means, peers, m)
                if result is not None:
                    _, n, below, _, _, needed, ok = result
                    verdicts.append(f"{label} {below}/{n} {'PASS' if ok else 'FAIL'}")
            if verdicts:
                print(f"{'':>6}   the same test on it: {', '.join(verdicts)}")
    print("runs per vqtex texture row:", dict(sorted(runs_per_row.items())))


if __name__ == "__main__":
    main()
