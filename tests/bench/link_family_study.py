#!/usr/bin/env python3
"""The natural model's cross-check (docs/guide/conventions.md, "Models"): would a tuned link
beat the untuned tanh?

For a one-parameter family of sigmoid links, sigma_p(z) = 1/2 + z / (2 (1 + |z|^p)^(1/p))
(p = 2 is rgb2spec's sigmoid), and for the shipped tanh link, reconstructs each measured
reflectance of data/ (ColorChecker 24, AMPAS 190) from its colour under D65 as the exact
spectrum of smoothest link (minimise sum (z[i+1] - z[i])^2 s.t. W sigma(z) = W rho, Newton on
the Lagrangian with a step cap), and prints CIEDE2000 median / p95 / max under A and FL11 per
set. Tuning p on one set and reading the other shows whether a parameter would generalise.
Independent of the library: the weights are the trapezoid rule on the 1 nm CIE tables of
data/ (docs/DESIGN.md §3), the colour maths written out here.

Usage: link_family_study.py [p ...]     (default: 1.5 2 3 4 6, then tanh)
"""
import csv
import os
import sys

import numpy as np

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data")
GRID = np.arange(380.0, 781.0, 5.0)


def table(name):
    rows = list(csv.reader(open(os.path.join(DATA, name))))
    head, d = rows[0], np.array([[float(v) for v in r] for r in rows[1:]])
    return head, d


def weights(light):
    """(3, N) weights of the grid's tent functions under `light` on the 1 nm CMF table."""
    _, cmf = table("cie1931_2deg_cmf_1nm.csv")
    nm = cmf[:, 0]
    tau = np.ones_like(nm)
    tau[0] = tau[-1] = 0.5
    tents = np.maximum(0.0, 1.0 - np.abs(nm[:, None] - GRID[None, :]) / 5.0)
    return ((tau * light(nm))[:, None] * cmf[:, 1:4]).T @ tents


def illuminant(name, column=None):
    head, d = table(name)
    c = head.index(column) if column else 1
    return lambda nm: np.interp(nm, d[:, 0], d[:, c])


W_D65 = weights(illuminant("cie_illuminant_d65_1nm.csv"))
W_A = weights(illuminant("cie_illuminant_a_1nm.csv"))
W_F11 = weights(illuminant("cie_illuminants_fl_hp_led_5nm.csv", "FL11"))
N = GRID.size
D = np.diff(np.eye(N), axis=0)
H = D.T @ D


def sets():
    for label, name in (("ColorChecker", "colorchecker_n_ohta_5nm.csv"),
                        ("AMPAS 190", "ampas_rawtoaces_190_patches_5nm.csv")):
        _, d = table(name)
        assert np.allclose(d[:, 0], GRID)
        yield label, np.clip(d[:, 1:].T, 0.0, 1.0)


def lab(xyz, white):
    t = xyz / white
    f = np.where(t > (6 / 29) ** 3, np.cbrt(np.maximum(t, 0)), t / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def de2000(p, q):
    (L1, a1, b1), (L2, a2, b2) = p, q
    cb = (np.hypot(a1, b1) + np.hypot(a2, b2)) / 2
    g = 0.5 * (1 - np.sqrt(cb**7 / (cb**7 + 25.0**7)))
    a1, a2 = (1 + g) * a1, (1 + g) * a2
    c1, c2 = np.hypot(a1, b1), np.hypot(a2, b2)
    h1, h2 = np.degrees(np.arctan2(b1, a1)) % 360, np.degrees(np.arctan2(b2, a2)) % 360
    dh = h2 - h1
    dh = 0 if c1 * c2 == 0 else (dh - 360 if dh > 180 else dh + 360 if dh < -180 else dh)
    dH = 2 * np.sqrt(c1 * c2) * np.sin(np.radians(dh / 2))
    lb, cbp, hs = (L1 + L2) / 2, (c1 + c2) / 2, h1 + h2
    hb = hs if c1 * c2 == 0 else hs / 2 if abs(h1 - h2) <= 180 else (hs + 360) / 2 if hs < 360 else (hs - 360) / 2
    t = (1 - 0.17 * np.cos(np.radians(hb - 30)) + 0.24 * np.cos(np.radians(2 * hb))
         + 0.32 * np.cos(np.radians(3 * hb + 6)) - 0.20 * np.cos(np.radians(4 * hb - 63)))
    rc = 2 * np.sqrt(cbp**7 / (cbp**7 + 25.0**7))
    sl = 1 + 0.015 * (lb - 50) ** 2 / np.sqrt(20 + (lb - 50) ** 2)
    sc, sh = 1 + 0.045 * cbp, 1 + 0.015 * cbp * t
    rt = -np.sin(np.radians(60 * np.exp(-(((hb - 275) / 25) ** 2)))) * rc
    return np.sqrt(((L2 - L1) / sl) ** 2 + ((c2 - c1) / sc) ** 2 + (dH / sh) ** 2
                   + rt * ((c2 - c1) / sc) * (dH / sh))


def link_p(p):
    s = lambda z: 0.5 + 0.5 * z / (1 + np.abs(z) ** p) ** (1 / p)
    d1 = lambda z: 0.5 * (1 + np.abs(z) ** p) ** (-1 / p - 1)
    d2 = lambda z: -0.5 * (1 + 1 / p) * p * np.abs(z) ** (p - 1) * np.sign(z) * (
        1 + np.abs(z) ** p) ** (-1 / p - 2)
    return s, d1, d2


TANH = (lambda z: 0.5 * (np.tanh(z) + 1), lambda z: 0.5 / np.cosh(z) ** 2,
        lambda z: -np.tanh(z) / np.cosh(z) ** 2)


def solve(t, link, iterations=300):
    s, d1, d2 = link
    z, lam = np.zeros(N), np.zeros(3)
    for _ in range(iterations):
        a = W_D65.T @ lam
        j = np.zeros((N + 3, N + 3))
        j[:N, :N] = H - np.diag(d2(z) * a)
        j[:N, N:] = -(d1(z)[:, None] * W_D65.T)
        j[N:, :N] = W_D65 * d1(z)
        step = np.linalg.solve(j, -np.concatenate([H @ z - d1(z) * a, W_D65 @ s(z) - t]))
        m = np.abs(step[:N]).max()
        f = min(1.0, 2.0 / m)
        z, lam = z + f * step[:N], lam + f * step[N:]
        if f == 1.0 and m < 1e-10:
            return s(z), True
    return s(z), False


def report(name, link):
    out = []
    for label, rho in sets():
        de = {"A": [], "FL11": []}
        fails = 0
        for r in rho:
            x, ok = solve(W_D65 @ r, link)
            fails += not ok
            for light, w in (("A", W_A), ("FL11", W_F11)):
                white = w @ np.ones(N)
                de[light].append(de2000(lab(w @ r, white), lab(w @ x, white)))
        cells = [f"{k} {np.median(v):.2f} / {np.percentile(v, 95):.2f}" for k, v in de.items()]
        out.append(f"{label}: " + ", ".join(cells) + (f" ({fails} not converged)" if fails else ""))
    print(f"{name:8s} " + " | ".join(out), flush=True)


if __name__ == "__main__":
    for p in [float(a) for a in sys.argv[1:]] or [1.5, 2, 3, 4, 6]:
        report(f"p={p:g}", link_p(p))
    report("tanh", TANH)
