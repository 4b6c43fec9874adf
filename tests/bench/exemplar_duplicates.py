#!/usr/bin/env python3
"""How much of the exemplar model's cross-validated gain comes from near-duplicates.

The two development sets share materials: some AMPAS 190 patches are remeasurements of the
ColorChecker's (reflectance RMS 0.004-0.02 from a ColorChecker patch). Scoring one set with the
other's measurements as exemplars then partly scores a patch with its own measurement. This
reruns the exemplar model's cross-validation of docs/MODEL_STUDY.md (local CIEDE2000 metric, one
projection; h = 2, c = 0.1 as shipped, and the folds' own picks) with every library spectrum
within a reflectance RMS `tau` of the scored patch removed from its library, for a few `tau`.

Uses tail_study.py's independent colorimetry and natural solver (NumPy). About 2 min on one core.
Usage: exemplar_duplicates.py
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import tail_study as T  # noqa: E402


def rms(a, b):
    return float(np.sqrt(((np.clip(a, 0, 1) - np.clip(b, 0, 1)) ** 2).mean()))


def blend(library, h, c, tau):
    """The exemplar model with `library` as exemplars, less those within RMS tau of the patch."""
    pool, labs = T.SETS[library], T.LAB_D65[library]
    metrics = [T.local_metric(l) for l in labs]

    def reconstruct(s, sp, i, t):
        x = T.natural(s, sp, i, t)
        target = T.lab(t, T.W_REF)
        d = np.array([T.local_de(q)(target, l) for q, l in zip(metrics, labs)])
        own = T.SETS[s][i]
        d[[j for j in range(len(pool)) if rms(pool[j], own) < tau]] = np.inf
        u = d / h
        w = np.where(u < 1, (1 - u * u) ** 3, 0.0)
        if not w.any():
            return x
        acc = c * x + sum(w[j] * np.clip(pool[j], 0, 1) for j in np.nonzero(w)[0])
        return T.exact_least_squares(acc / (c + w.sum()), t)
    return reconstruct


def main():
    natural = T.evaluate(T.natural)
    s0, p0 = T.score(natural)
    near = {s: sum(min(rms(a, b) for b in T.SETS[T.OTHER[s]]) < 0.02 for a in T.SETS[s])
            for s in T.SETS}
    print(f"patches with a measurement of the other set within RMS 0.02: {near}")
    print(f"natural: S = {s0:.3f}, worst p95 {p0:.2f}")
    for tau in (0.0, 0.02, 0.05):
        for label, picks in (("shipped (2, 0.1)", {"ColorChecker": (2, 0.1), "AMPAS 190": (2, 0.1)}),
                             ("folds' picks", {"ColorChecker": (10, 1), "AMPAS 190": (2, 0.1)})):
            cells = {}
            for held in T.SETS:
                cells.update(T.evaluate(blend(T.OTHER[held], *picks[held], tau), [held]))
            s, p = T.score(cells)
            worse = sum(cells[k][0] > natural[k][0] + 0.05 or cells[k][1] > natural[k][1] + 0.2
                        for k in cells)
            a = {k[0]: cells[k][0] for k in cells if k[1] == "Rec.2020" and k[2] == "A"}
            print(f"tau {tau:.2f}, {label}: S = {s:.3f}, worst p95 {p:.2f}, cells worse than "
                  f"natural by the rule: {worse}; Rec.2020 under A, median: ColorChecker "
                  f"{a['ColorChecker']:.2f}, AMPAS 190 {a['AMPAS 190']:.2f}", flush=True)


if __name__ == "__main__":
    main()
