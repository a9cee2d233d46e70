#!/usr/bin/python3
"""The acceptance test for atlas choices simulated offline
(docs/studies/2026-11-24-atlas-choice-per-texture.md): a choice rule
picks one candidate per texture from atlas-choice CSVs by their proxy
scores (p_*, what the encoder can see),
and its held-out scores (h_*, computed as vqtex-bench computes them) are
compared with the PEER+synth rows of a vqtex-bench CSV, as vqtex-bench's
summary does: per metric, the best peer is the lowest mean among the peers
that scored the most textures (bench/acceptance.py's best_peer), and the verdict needs vqtex's mean at or below
it and vqtex at or below it on two thirds of the textures.

Offline, because a bench run per rule would take minutes each and the
candidates' files do not change with the rule. The peers were given the
bench's own vqtex file sizes as budgets, so a choice of other sizes would
give them slightly other budgets: confirm a kept rule with vqtex-bench.

Usage: bench/choice_rules.py BENCH.csv TAG=ATLAS_CHOICE.csv [TAG=...]
The first TAG's whole-example candidate (side 128, x 0) is the reference
of the relative rules."""
import collections
import csv
import sys

import acceptance

METRICS = tuple(label for label, _ in acceptance.METRICS)


def bench_rows(path):
    """rate -> codec -> texture -> (completeness, swd, coherence): the bench's
    vqtex and peer rows, read as acceptance.py reads them."""
    rows, _ = acceptance.read_runs([path])
    return {rate: {codec: acceptance.averaged(textures) for codec, textures in codecs.items()}
            for rate, codecs in rows.items()}


def candidates(specs):
    """rate -> texture -> [candidate dict], over every TAG=CSV given."""
    out = collections.defaultdict(lambda: collections.defaultdict(list))
    for spec in specs:
        tag, path = spec.split("=", 1)
        for r in csv.DictReader(open(path)):
            out[int(r["target"])][r["texture"]].append({
                "key": (tag, int(r["side"]), int(r["x"]) > 0),
                "h": (float(r["h_compl"]), float(r["h_swd"]), float(r["h_coh"])),
                "p": (float(r["p_compl"]), float(r["p_swd"]), float(r["p_coh"]))})
    return out


def verdict(peers, chosen):
    """The acceptance line of vqtex-bench for texture -> scores (the test is
    acceptance.best_peer's, the bench's own rules)."""
    parts = []
    for m, label in enumerate(METRICS):
        result = acceptance.best_peer(chosen, peers, m)
        if result is None:
            parts.append(label + " n/a")
            continue
        codec, _, count, mine, peer_mean, _, ok = result
        parts.append("%s %.2f vs %s %.2f [%d] %s" % (label, mine, codec.split("+")[0], peer_mean, count,
                                                      "pass" if ok else "FAIL"))
    return " | ".join(parts)


def current_rule(whole, cands):
    """The encoder's rule (atlas_choice.cpp): the candidates whose proxy
    completeness is no worse than the whole example's, then the lowest sum
    of SWD and coherence, each relative to the whole example's."""
    best, best_score = whole, 2.0
    for c in cands:
        if c is whole or c["p"][0] > whole["p"][0]:
            continue
        score = c["p"][1] / whole["p"][1] + c["p"][2] / whole["p"][2]
        if score < best_score:
            best, best_score = c, score
    return best


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    bench = bench_rows(sys.argv[1])
    specs = sys.argv[2:]
    cands = candidates(specs)
    reference = (specs[0].split("=", 1)[0], 128, False)
    for rate in sorted(cands):
        if rate not in bench:
            continue
        peers = {c: rows for c, rows in bench[rate].items() if c.endswith("+synth")}
        for codec, rows in bench[rate].items():
            if codec.startswith("vqtex"):
                print("%5d %-34s %s" % (rate, "vqtex-bench's own row", verdict(peers, rows)))
        textures = cands[rate]
        keys = sorted({c["key"] for t in textures.values() for c in t})
        for key in keys:
            chosen = {t: c["h"] for t, cs in textures.items() for c in cs if c["key"] == key}
            if len(chosen) == len(textures):
                print("%5d %-34s %s" % (rate, "always %s %d %s" % (key[0], key[1], "centre" if key[2] else "top-left"),
                                        verdict(peers, chosen)))
        chosen, changed = {}, 0
        for t, cs in textures.items():
            whole = next(c for c in cs if c["key"] == reference)
            pick = current_rule(whole, cs)
            chosen[t] = pick["h"]
            changed += pick is not whole
        print("%5d %-34s %s" % (rate, "encoder's rule (%d not whole)" % changed, verdict(peers, chosen)))


if __name__ == "__main__":
    main()
