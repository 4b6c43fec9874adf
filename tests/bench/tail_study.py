#!/usr/bin/env python3
"""The model study of docs/MODEL_STUDY.md: candidates for spectra that end like real materials.

Every candidate reconstructs each measured reflectance of data/ (ColorChecker 24, AMPAS 190) from
its colour under D65, given as RGB in Linear Rec.709 (clipped to [0, 1] as a texture holds it)
and in Linear Rec.2020, as an exact bounded spectrum, and is scored by CIEDE2000 against the
measurement under A, FL11, FL2, LED-B3, HP1 and D50 (CIELAB relative to rho == 1 under the
light): 24 cells of median / p95 / max. Candidates that learn anything (data statistics, a
constant from a grid) are cross-validated: fitted on one set, scored on the other, both ways,
with constants picked inside the training set by the rule of docs/MODEL_STUDY.md restricted to
its 12 cells. The rule then picks the winner.

Independent of the library: the weights are the trapezoid rule on the 1 nm CIE tables of data/
(docs/DESIGN.md §3), RGB spaces from their primaries, the colour maths written out here. The
natural model's numbers agree with `make validate` to the third decimal.

Usage: tail_study.py [CACHE_DIR]   (/usr/bin/python3: NumPy; ~1 h on one core, results of each
       candidate cached in CACHE_DIR when given, so a rerun only prints)
"""
import csv
import itertools
import os
import pickle
import sys

import numpy as np

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data")
GRID = np.arange(380.0, 781.0, 5.0)
N = GRID.size
H = 5.0  # grid step, nm


def table(name):
    rows = list(csv.reader(open(os.path.join(DATA, name))))
    return rows[0], np.array([[float(v) if v else 0.0 for v in r] for r in rows[1:]])


_, CMF = table("cie1931_2deg_cmf_1nm.csv")
NM = CMF[:, 0]
TAU = np.ones_like(NM)
TAU[0] = TAU[-1] = 0.5
TENTS = np.maximum(0.0, 1.0 - np.abs(NM[:, None] - GRID[None, :]) / H)


def weights(spd):
    """(3, N) weights of the grid's tents under a light, normalised so that rho == 1 has Y = 1."""
    w = ((TAU * spd)[:, None] * CMF[:, 1:4]).T @ TENTS
    return w / w[1].sum()


def illuminant(name):
    files = {"D65": "cie_illuminant_d65_1nm.csv", "A": "cie_illuminant_a_1nm.csv",
             "D50": "cie_illuminant_d50_1nm.csv"}
    if name in files:
        head, d = table(files[name])
        c = 1
    else:
        head, d = table("cie_illuminants_fl_hp_led_5nm.csv")
        c = head.index(name)
    return np.interp(NM, d[:, 0], d[:, c])  # extended by the end values, as the library does


LIGHTS = ["A", "FL11", "FL2", "LED-B3", "HP1", "D50"]
W = weights(illuminant("D65"))
W_LIGHT = {light: weights(illuminant(light)) for light in LIGHTS}
W_REF = W.sum(axis=1)
W_D65 = np.array([0.3127 / 0.3290, 1, (1 - 0.3127 - 0.3290) / 0.3290])


def rgb_to_xyz(p):
    m = np.array([[x / y, 1, (1 - x - y) / y] for x, y in (p[0:2], p[2:4], p[4:6])]).T
    return m * np.linalg.solve(m, W_D65)[None, :]


SPACES = {"Rec.709": rgb_to_xyz([0.64, 0.33, 0.30, 0.60, 0.15, 0.06]),
          "Rec.2020": rgb_to_xyz([0.708, 0.292, 0.170, 0.797, 0.131, 0.046])}
SET_FILES = {"ColorChecker": "colorchecker_n_ohta_5nm.csv",
             "AMPAS 190": "ampas_rawtoaces_190_patches_5nm.csv"}
SETS = {name: table(f)[1][:, 1:].T.copy() for name, f in SET_FILES.items()}
OTHER = {"ColorChecker": "AMPAS 190", "AMPAS 190": "ColorChecker"}


def targets(rho, space):
    """The white-balanced targets of the patches as a texture in `space` holds them."""
    m = SPACES[space]
    out = []
    for r in rho:
        rgb = np.clip(np.linalg.solve(m, W @ r * W_D65 / W_REF), 0, 1)
        out.append(m @ rgb * W_REF / W_D65)
    return np.array(out)


TARGETS = {(s, sp): targets(SETS[s], sp) for s in SETS for sp in SPACES}


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
    hb = (hs if c1 * c2 == 0 else hs / 2 if abs(h1 - h2) <= 180
          else (hs + 360) / 2 if hs < 360 else (hs - 360) / 2)
    t = (1 - 0.17 * np.cos(np.radians(hb - 30)) + 0.24 * np.cos(np.radians(2 * hb))
         + 0.32 * np.cos(np.radians(3 * hb + 6)) - 0.20 * np.cos(np.radians(4 * hb - 63)))
    rc = 2 * np.sqrt(cbp**7 / (cbp**7 + 25.0**7))
    sl = 1 + 0.015 * (lb - 50) ** 2 / np.sqrt(20 + (lb - 50) ** 2)
    sc, sh = 1 + 0.045 * cbp, 1 + 0.015 * cbp * t
    rt = -np.sin(np.radians(60 * np.exp(-(((hb - 275) / 25) ** 2)))) * rc
    return np.sqrt(((L2 - L1) / sl) ** 2 + ((c2 - c1) / sc) ** 2 + (dH / sh) ** 2
                   + rt * ((c2 - c1) / sc) * (dH / sh))


LAB_D65 = {s: np.array([lab(W @ r, W_REF) for r in v]) for s, v in SETS.items()}

# ---------------------------------------------------------------------------------------------
# Solvers: min 1/2 z'Qz - b'z  s.t.  W sigma(z) = t, sigma(z) = (tanh z + 1) / 2.


def sigma(z):
    s = 0.5 * (np.tanh(z) + 1)
    d1 = 2 * s * (1 - s)
    return s, d1, 2 * d1 * (1 - 2 * s)


def logit(r):
    r = np.clip(r, 0.005, 0.995)
    return 0.5 * np.log(r / (1 - r))


D1 = np.diff(np.eye(N), axis=0)
D2 = np.diff(np.eye(N), 2, axis=0)
H_NATURAL = D1.T @ D1


def project(z, t):
    """The binary-entropy projection z + W'nu onto W sigma = t (docs/DESIGN.md §6): exact,
    bounded, z itself when sigma(z) is exact. Returns the link."""
    nu = np.zeros(3)
    for _ in range(100):
        s, d1, _ = sigma(z + W.T @ nu)
        grad = W @ s - t
        if np.abs(grad).max() <= 1e-13 * np.abs(t).max():
            break
        step = -np.linalg.solve((W * d1) @ W.T, grad)
        a = 1.0
        while a > 1e-6 and (W @ sigma(z + W.T @ (nu + a * step))[0] - t) @ step > 0:
            a *= 0.5
        nu += a * step
    return z + W.T @ nu


def solve_link(t, q, b=None, z0=None, iterations=100):
    """Newton on the Lagrangian (step cap 4, convexified where the Hessian is indefinite), from
    the grey of the target's luminance unless z0 is given, polished by project()."""
    b = np.zeros(N) if b is None else b
    p = t[1] / W[1].sum()
    z = np.full(N, 0.5 * np.log(p / (1 - p))) if z0 is None else z0.copy()
    lam = np.zeros(3)
    qr = q + 2e-9 * np.eye(N)
    for _ in range(iterations):
        s, d1, d2 = sigma(z)
        a = W.T @ lam
        curvature = -d2 * a
        hess = qr + np.diag(curvature)
        try:
            np.linalg.cholesky(hess)
        except np.linalg.LinAlgError:
            hess = qr + np.diag(np.maximum(curvature, 0))
        j = W * d1
        kkt = np.block([[hess, -j.T], [j, np.zeros((3, 3))]])
        step = np.linalg.solve(kkt, np.concatenate([-(qr @ z - b - d1 * a), t - W @ s]))
        m = np.abs(step[:N]).max()
        f = min(1.0, 4.0 / m)
        z += f * step[:N]
        lam += f * step[N:]
        if f == 1.0 and m < 1e-9 * max(1, np.abs(z).max()):
            break
    return project(z, t)


NATURAL_Z = {}


def natural_link(key, t):
    if key not in NATURAL_Z:
        NATURAL_Z[key] = solve_link(t, H_NATURAL)
    return NATURAL_Z[key]


def exact_least_squares(x0, t):
    """The closest spectrum to x0 with W x = t, 0 <= x <= 1 (dual Newton on the clamp)."""
    nu = np.zeros(3)
    for _ in range(200):
        v = x0 + W.T @ nu
        grad = W @ np.clip(v, 0, 1) - t
        if np.abs(grad).max() <= 1e-13 * np.abs(t).max():
            break
        free = (v > 0) & (v < 1)
        step = -np.linalg.solve(W[:, free] @ W[:, free].T + 1e-12 * np.eye(3), grad)
        a = 1.0
        while a > 1e-9 and (W @ np.clip(x0 + W.T @ (nu + a * step), 0, 1) - t) @ step > 0:
            a *= 0.5
        nu += a * step
    return np.clip(x0 + W.T @ nu, 0, 1)


# ---------------------------------------------------------------------------------------------
# Scoring.


def spread(v):
    v = np.sort(v)
    return float(np.median(v)), float(np.percentile(v, 95)), float(v[-1])


def evaluate(reconstruct, sets=SETS):
    """reconstruct(set, space, index, target) -> spectrum; the cells of `sets`."""
    out = {}
    for s in sets:
        rho = SETS[s]
        for sp in SPACES:
            xs = [reconstruct(s, sp, i, t) for i, t in enumerate(TARGETS[(s, sp)])]
            for light in LIGHTS:
                w = W_LIGHT[light]
                white = w.sum(axis=1)
                out[(s, sp, light)] = spread(
                    [de2000(lab(w @ r, white), lab(w @ x, white)) for r, x in zip(rho, xs)])
    return out


def score(cells, sets=None):
    """(largest median, largest p95) over the cells of `sets`."""
    chosen = [c for c in cells if sets is None or c[0] in sets]
    return max(cells[c][0] for c in chosen), max(cells[c][1] for c in chosen)


def best_of(options, cells_of):
    """The rule: the lowest worst median; within 0.01 of it, the lowest worst p95."""
    lowest = min(cells_of(o)[0] for o in options)
    return min((o for o in options if cells_of(o)[0] <= lowest + 0.01), key=lambda o: cells_of(o)[1])


class Study:
    def __init__(self, cache):
        self.cache = cache
        self.rows = []  # (name, note, cells)

    def cached(self, key, compute):
        path = os.path.join(self.cache, key.replace("/", "_") + ".pkl") if self.cache else None
        if path and os.path.exists(path):
            return pickle.load(open(path, "rb"))
        value = compute()
        if path:
            pickle.dump(value, open(path, "wb"))
        return value

    def fixed(self, name, grid, make, note=""):
        """A family with constants from `grid` and nothing learned: every point on both sets;
        each set scored with the point the other set picks."""
        results = {p: self.cached(f"{name}-{p}", lambda p=p: evaluate(make(*p))) for p in grid}
        cells, picks = {}, {}
        for held in SETS:
            train = OTHER[held]
            pick = best_of(list(grid), lambda p: score(results[p], [train]))
            picks[held] = pick
            cells.update({c: v for c, v in results[pick].items() if c[0] == held})
        self.add(name, cells, note or self.picked(picks, grid))
        return results

    def fitted(self, name, grid, make, note=""):
        """A family that learns from its training set: make(train, *p) -> reconstruct. Each
        point fitted on each set and scored on both; the constant picked in-sample on the
        training set, the held-out set scored with it."""
        results = {(p, f): self.cached(f"{name}-{p}-{f}", lambda p=p, f=f: evaluate(make(f, *p)))
                   for p in grid for f in SETS}
        cells, picks = {}, {}
        for held in SETS:
            train = OTHER[held]
            pick = best_of(list(grid), lambda p: score(results[(p, train)], [train]))
            picks[held] = pick
            cells.update({c: v for c, v in results[(pick, train)].items() if c[0] == held})
        self.add(name, cells, note or self.picked(picks, grid))
        return results

    @staticmethod
    def picked(picks, grid):
        if len(grid) == 1:
            return ""
        return "; ".join(f"fitted on {OTHER[h]}: {picks[h]}" for h in SETS)

    def add(self, name, cells, note):
        self.rows.append((name, note, cells))
        s, p = score(cells)
        print(f"{name}: S = {s:.3f}, worst p95 {p:.2f}  {note}", flush=True)


# ---------------------------------------------------------------------------------------------
# Candidates.


def smoothstep(u):
    v = np.clip(u + 0.5, 0, 1)
    return v * v * (3 - 2 * v)


def tail_blend(lam, lb, lr, w):
    """0 in the middle, 1 below lb and above lr, a smooth step of width w around each."""
    return np.clip(smoothstep((lam - lr) / w) + smoothstep((lb - lam) / w), 0, 1)


MID1 = 0.5 * (GRID[1:] + GRID[:-1])  # where the first differences sit
MID2 = GRID[1:-1]  # where the second differences sit


def with_penalty(q, b=None):
    return lambda s, sp, i, t: sigma(solve_link(t, q, b, z0=natural_link((s, sp, i), t)))[0]


def natural(s, sp, i, t):
    return sigma(natural_link((s, sp, i), t))[0]


def tail_trend(lb, lr, w, tau, damped=False):
    """1/2 sum (1 - b) (dz)^2 + 1/2 (tau/h)^2 sum b (d2z)^2 (damped: first differences
    everywhere, so the trend decays over tau instead of continuing)."""
    b1, b2 = tail_blend(MID1, lb, lr, w), tail_blend(MID2, lb, lr, w)
    a1 = np.ones_like(b1) if damped else 1 - b1
    return with_penalty(D1.T @ (a1[:, None] * D1) + (tau / H) ** 2 * D2.T @ (b2[:, None] * D2))


SENSITIVITY = np.interp(MID1, NM, CMF[:, 1:4].sum(1))
SENSITIVITY /= SENSITIVITY.max()


def observer_weighted(p):
    """First differences weighted by the observer's sensitivity to the power p (floor 1e-3)."""
    w = np.maximum(SENSITIVITY, 1e-3) ** p
    return with_penalty(D1.T @ (w[:, None] * D1))


def momentum(phi):
    """1/2 sum (dz_i - phi dz_{i-1})^2: increments that keep a fraction phi of the last one."""
    rows = D1.copy()
    rows[1:] -= phi * D1[:-1]
    return with_penalty(rows.T @ rows)


def markov(train, kappa):
    """Learned second-order autoregression z_i = a z_{i-1} + b z_{i-2} + c + e (variance per
    wavelength), ridge-shrunk to the random walk with strength kappa x the set's size."""
    z = logit(SETS[train])
    n = len(z)
    rows, cs, var = [], [], []
    for i in range(1, N):
        cols = [z[:, i - 1]] + ([z[:, i - 2]] if i >= 2 else []) + [np.ones(n)]
        x = np.column_stack(cols)
        prior = np.array([1.0] + ([0.0] if i >= 2 else []) + [0.0])
        coef = np.linalg.solve(x.T @ x + kappa * n * np.eye(len(prior)),
                               x.T @ z[:, i] + kappa * n * prior)
        row = np.zeros(N)
        row[i], row[i - 1] = 1, -coef[0]
        if i >= 2:
            row[i - 2] = -coef[1]
        rows.append(row)
        cs.append(coef[-1])
        var.append(((z[:, i] - x @ coef) ** 2).mean() + 1e-6)
    rows, cs, var = np.array(rows), np.array(cs), np.array(var)
    q = rows.T @ (rows / var[:, None])
    scale = 1 / np.diag(q).max()
    return with_penalty(q * scale, rows.T @ (cs / var) * scale)


def mean_shape(train, s):
    """The random walk around s x the training set's mean logit."""
    mu = s * logit(SETS[train]).mean(0)
    return with_penalty(H_NATURAL, H_NATURAL @ mu)


def low_rank(train, k, sigma2):
    """A Gaussian prior: the training set's mean, covariance sigma2 m (D'D + 1e-4 I)^-1 plus its
    k principal components (m: the data's mean squared step)."""
    z = logit(SETS[train])
    mu = z.mean(0)
    zc = z - mu
    ev, u = np.linalg.eigh(zc.T @ zc / len(z))
    ev, u = ev[::-1][:k], u[:, ::-1][:, :k]
    step2 = (np.diff(zc, axis=1) ** 2).mean()
    cov = sigma2 * step2 * np.linalg.inv(H_NATURAL + 1e-4 * np.eye(N)) + (u * ev) @ u.T
    q = np.linalg.inv(cov)
    scale = 1 / np.diag(q).max()
    return with_penalty(q * scale, q @ mu * scale)


def tail_drift(train, lb, lr, w):
    """1/2 sum (dz_i - m_i)^2, m the training set's mean increment, only in the tails."""
    m = np.diff(logit(SETS[train]), axis=1).mean(0) * tail_blend(MID1, lb, lr, w)
    return with_penalty(H_NATURAL, D1.T @ m)


def tail_extrapolation(lb, lr, m):
    """The natural link beyond lb / lr replaced by the line through the cut with the slope
    fitted over the m nm before it, projected back onto the exact spectra."""
    def reconstruct(s, sp, i, t):
        z = natural_link((s, sp, i), t).copy()
        for cut, sign in ((np.searchsorted(GRID, lb), -1), (np.searchsorted(GRID, lr), 1)):
            window = np.arange(cut - sign * int(m / H), cut + sign, sign)
            slope = np.polyfit(GRID[window], z[window], 1)[0]
            tail = np.arange(cut + sign, N if sign > 0 else -1, sign)
            z[tail] = z[cut] + slope * (GRID[tail] - GRID[cut])
        return sigma(project(z, t))[0]
    return reconstruct


def mean_reversion(lb, lr, w, ell):
    """Tails pulled to z = 0 (rho = 1/2) over a length ell: a failure kept for the record."""
    g = tail_blend(GRID, lb, lr, w) / (ell / H) ** 2
    return with_penalty(H_NATURAL + np.diag(g))


def de76(p, q):
    return float(np.sqrt(((np.asarray(p) - np.asarray(q)) ** 2).sum()))


def local_metric(l):
    """CIEDE2000's metric at the colour l (kL = kC = kH = 1): the quadratic form Q with
    dE^2 = d' Q d for a small step d in CIELAB, its S_L, S_C, S_H, R_T and a' stretch G taken at
    l. A smooth, continuous stand-in for CIEDE2000 at small distances (CIEDE2000 itself jumps
    where the mean hue wraps)."""
    L, a, b = l
    c = np.hypot(a, b)
    g = 0.5 * (1 - np.sqrt(c**7 / (c**7 + 25.0**7)))
    ap = (1 + g) * a
    cp = np.hypot(ap, b)
    hp = np.degrees(np.arctan2(b, ap)) % 360
    t = (1 - 0.17 * np.cos(np.radians(hp - 30)) + 0.24 * np.cos(np.radians(2 * hp))
         + 0.32 * np.cos(np.radians(3 * hp + 6)) - 0.20 * np.cos(np.radians(4 * hp - 63)))
    sl = 1 + 0.015 * (L - 50) ** 2 / np.sqrt(20 + (L - 50) ** 2)
    sc, sh = 1 + 0.045 * cp, 1 + 0.015 * cp * t
    rt = -np.sin(np.radians(60 * np.exp(-(((hp - 275) / 25) ** 2)))) * 2 * np.sqrt(cp**7 / (cp**7 + 25.0**7))
    # (dC', dH') = R (da', db) with R the rotation to the radial and tangential directions.
    u = np.array([ap, b]) / cp if cp > 0 else np.array([1.0, 0.0])
    rot = np.array([u, [-u[1], u[0]]])
    inner = np.array([[1 / sc**2, rt / (2 * sc * sh)], [rt / (2 * sc * sh), 1 / sh**2]])
    ab = rot.T @ inner @ rot @ np.diag([1 + g, 1.0])
    ab = np.diag([1 + g, 1.0]) @ ab
    q = np.zeros((3, 3))
    q[0, 0] = 1 / sl**2
    q[1:, 1:] = ab
    return q


def local_de(q):
    """The distance function of a library colour's local metric: target, library lab -> dE."""
    return lambda target, l: float(np.sqrt(max(0.0, (target - l) @ q @ (target - l))))


def kernel_blend(libraries, h, c, metric=de2000, leave_out=False, project_once=False):
    """(c x natural + sum_j w_j P(rho_j)) / (c + sum_j w_j): the library's measured spectra
    (the sets named in `libraries`), each projected onto the target's exact spectra (least
    squares within the bounds), with the compact weights w_j = (1 - (d_j / h)^2)^3 of their
    colour distance `metric` under D65: continuous in the colour, exact and bounded as a convex
    combination of exact bounded spectra. leave_out: the scored patch is not in its own library.
    project_once: (c x natural + sum_j w_j rho_j) / (c + sum_j w_j) projected once instead (one
    projection per colour rather than one per neighbour; natural itself where no weight is)."""
    pool = np.vstack([SETS[l] for l in libraries])
    labs = np.vstack([LAB_D65[l] for l in libraries])
    owner = [(l, j) for l in libraries for j in range(len(SETS[l]))]
    metrics = [local_metric(l) for l in labs] if metric == "local" else None

    def reconstruct(s, sp, i, t):
        x = natural(s, sp, i, t)
        target = lab(t, W_REF)
        if metric == "local":
            d = np.array([local_de(q)(target, l) for q, l in zip(metrics, labs)])
        else:
            d = np.array([metric(target, q) for q in labs])
        if leave_out and (s, i) in owner:
            d[owner.index((s, i))] = np.inf
        u = d / h
        w = np.where(u < 1, (1 - u * u) ** 3, 0.0)
        if not w.any():
            return x
        acc = c * x
        for j in np.nonzero(w)[0]:
            rho = np.clip(pool[j], 0, 1)
            acc = acc + w[j] * (rho if project_once else exact_least_squares(rho, t))
        acc = acc / (c + w.sum())
        return exact_least_squares(acc, t) if project_once else acc
    return reconstruct


def kernel_family(st, name, metric, project_once=False):
    """The kernel blend, cross-validated: (h, c) picked on the training set with each patch
    left out of its own library, then the whole training set is the library of the held-out
    set. Also the constants a shipped model would take: picked the same way on both sets
    together (each patch left out of the union)."""
    grid = [(h, c) for h in (2, 5, 10) for c in (0.1, 1, 10)]
    inner = {(p, f): st.cached(f"{name}-inner-{p}-{f}", lambda p=p, f=f: evaluate(
        kernel_blend([f], *p, metric=metric, leave_out=True, project_once=project_once), [f]))
        for p in grid for f in SETS}
    cells, picks = {}, {}
    for held in SETS:
        train = OTHER[held]
        picks[held] = best_of(grid, lambda p: score(inner[(p, train)]))
        cells.update(st.cached(f"{name}-{picks[held]}-{train}", lambda: evaluate(
            kernel_blend([train], *picks[held], metric=metric, project_once=project_once),
            [held])))
    st.add(name, cells, Study.picked(picks, grid))
    union = {p: st.cached(f"{name}-union-{p}", lambda p=p: evaluate(
        kernel_blend(list(SETS), *p, metric=metric, leave_out=True, project_once=project_once)))
        for p in grid}
    shipped = best_of(grid, lambda p: score(union[p]))
    s, q = score(union[shipped])
    print(f"  {name}, both sets as the library (each patch left out): picks {shipped}, "
          f"S = {s:.3f}, worst p95 {q:.2f}", flush=True)
    return shipped, union[shipped]


def nearest_neighbour(k):
    """What data alone achieves: the k nearest other development patches by CIEDE2000 under
    D65 (k > 1: weighted by 1 / distance), projected onto the exact spectra of the colour."""
    pool = np.vstack([SETS["ColorChecker"], SETS["AMPAS 190"]])
    labs = np.vstack([LAB_D65["ColorChecker"], LAB_D65["AMPAS 190"]])
    def reconstruct(s, sp, i, t):
        d = np.array([de2000(lab(t, W_REF), q) for q in labs])
        d[i + (0 if s == "ColorChecker" else len(SETS["ColorChecker"]))] = np.inf
        idx = np.argsort(d)[:k]
        w = 1 / np.maximum(d[idx], 1e-9)
        return exact_least_squares(np.clip((w[:, None] * pool[idx]).sum(0) / w.sum(), 0, 1), t)
    return reconstruct


# ---------------------------------------------------------------------------------------------
# Report.


def markdown(study):
    nat = study.rows[0][2]
    head = ("| candidate | S (worst median) | worst p95 | cells worse than natural by > 0.05 "
            "(median) | Rec.2020 median A / FL11 / FL2 / LED-B3 / HP1 / D50: ColorChecker ; AMPAS 190 "
            "| notes |\n|---|---|---|---|---|---|\n")
    lines = []
    for name, note, cells in study.rows:
        s, p = score(cells)
        worse = sum(cells[c][0] > nat[c][0] + 0.05 for c in cells)
        meds = " ; ".join(" / ".join(f"{cells[(st, 'Rec.2020', l)][0]:.2f}" for l in LIGHTS)
                          for st in SETS)
        lines.append(f"| {name} | {s:.3f} | {p:.2f} | {worse} | {meds} | {note} |")
    return head + "\n".join(lines) + "\n"


def full_cells(cells):
    out = ["| set | space | " + " | ".join(LIGHTS) + " |", "|---|---|" + "---|" * len(LIGHTS)]
    for s in SETS:
        for sp in SPACES:
            out.append(f"| {s} | {sp} | " + " | ".join(
                "{:.2f} / {:.2f} / {:.2f}".format(*cells[(s, sp, l)]) for l in LIGHTS) + " |")
    return "\n".join(out) + "\n"


def main():
    cache = sys.argv[1] if len(sys.argv) > 1 else None
    if cache:
        os.makedirs(cache, exist_ok=True)
    st = Study(cache)
    # Declared before any number was computed (docs/MODEL_STUDY.md).
    st.fixed("natural", [()], lambda: natural)
    edges = list(itertools.product([400, 410, 420, 430, 440], [620, 640, 660, 680, 700]))
    st.fixed("tail trend", [e + (w, tau) for e in edges for w in (10, 40) for tau in (10, 30, 100)],
             tail_trend)
    st.fitted("learned Markov prior", [(k,) for k in (0.1, 1, 10, 100)], markov)
    st.fitted("learned mean shape", [(s,) for s in (0.25, 0.5, 1.0)], mean_shape)
    st.fitted("learned low-rank prior",
              [(k, s2) for k in (2, 4, 8) for s2 in (0.1, 1, 10)], low_rank)
    st.fixed("tail extrapolation", [e + (m,) for e in edges for m in (10, 20, 40)],
             tail_extrapolation)
    # Added after the first numbers (new twists, same rule).
    st.fixed("tail trend, damped",
             [e + (w, tau) for e in edges for w in (10, 40) for tau in (10, 30, 100)],
             lambda lb, lr, w, tau: tail_trend(lb, lr, w, tau, damped=True))
    st.fixed("observer-weighted first differences", [(p,) for p in (0.25, 0.5, 1.0)],
             observer_weighted)
    st.fixed("momentum (increments keep phi)", [(phi,) for phi in np.arange(1, 10) / 10],
             momentum)
    st.fitted("learned tail drift", [e + (20,) for e in edges], tail_drift)
    st.fixed("tail mean reversion (to rho = 1/2)",
             [(410, 640, 20, 20), (410, 640, 20, 50), (400, 660, 20, 30), (420, 620, 20, 50)],
             mean_reversion)
    union = {}
    union["kernel blend with the training set"] = kernel_family(
        st, "kernel blend with the training set", de2000)
    union["kernel blend, CIELAB distance"] = kernel_family(
        st, "kernel blend, CIELAB distance", de76)
    union["kernel blend, projected once"] = kernel_family(
        st, "kernel blend, projected once", de2000, project_once=True)
    union["kernel blend, CIEDE2000's local metric, projected once"] = kernel_family(
        st, "kernel blend, CIEDE2000's local metric, projected once", "local", project_once=True)

    # Reference lines (not candidates).
    references = [("nearest neighbour (leave one out), k = 1", nearest_neighbour(1)),
                  ("nearest neighbours (leave one out), k = 3", nearest_neighbour(3))]
    ref_cells = {name: st.cached(name.replace(" ", "_"), lambda f=f: evaluate(f))
                 for name, f in references}

    candidates = st.rows
    winner = best_of(list(range(len(candidates))), lambda k: score(candidates[k][2]))
    print("\n" + markdown(st))
    for name, cells in ref_cells.items():
        s, p = score(cells)
        print(f"reference: {name}: S = {s:.3f}, worst p95 {p:.2f}")
    nat = candidates[0][2]
    s0, p0 = score(nat)
    ws, wp = score(candidates[winner][2])
    # Every candidate that ties the winner on both criteria (the rule cannot tell them apart).
    tied = [k for k in range(len(candidates))
            if abs(score(candidates[k][2])[0] - ws) < 0.005 and abs(score(candidates[k][2])[1] - wp) < 0.005]
    print(f"\nwinner by the rule: {candidates[winner][0]} (S = {ws:.3f}, worst p95 {wp:.2f}; natural "
          f"{s0:.3f}, {p0:.2f}); tied with it on both: " + ", ".join(candidates[k][0] for k in tied))
    for k in tied:
        name, _, cells = candidates[k]
        s, p = score(cells)
        worse = [c for c in cells if cells[c][0] > nat[c][0] + 0.05 or cells[c][1] > nat[c][1] + 0.2]
        print(f"  {name}: registered (if exact etc.): {s < s0}; default: {s <= s0 - 0.05 and not worse}")
    for k in [0] + tied:
        print(f"\n{candidates[k][0]}, every cell (median / p95 / max):\n" + full_cells(candidates[k][2]))
    for n, c in ref_cells.items():
        print(f"\n{n}:\n" + full_cells(c))
    for n, (p, c) in union.items():
        print(f"\n{n}, both sets as the library, constants {p} (leave one out):\n" + full_cells(c))


if __name__ == "__main__":
    main()
