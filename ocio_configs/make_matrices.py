#!/usr/bin/env python3
"""Derive the RGB -> CIE XYZ (D65) matrices used in spectralize.ocio.

Standard normalised-primary-matrix (NPM) derivation, done in exact rational
arithmetic (fractions.Fraction) and only rounded when printed:

  * each primary (x, y) becomes the column (x/y, 1, (1-x-y)/y);
  * the white point (x_w, y_w) becomes W = (x_w/y_w, 1, (1-x_w-y_w)/y_w),
    i.e. XYZ of the white with Y = 1;
  * the column scales S solve P . S = W, so RGB (1,1,1) maps exactly to W;
  * NPM = P . diag(S).

For D65 (0.3127, 0.3290): W = (0.3127/0.3290, 1, 0.3583/0.3290)
                            = (0.95045592705..., 1, 1.08905775075...).

Usage:
  python3 make_matrices.py            # print matrices + YAML snippets
  python3 make_matrices.py --check spectralize.ocio
                                      # verify the config contains exactly
                                      # these matrices (exit 1 otherwise)
"""
from decimal import Decimal, getcontext
from fractions import Fraction as F
import re
import sys

getcontext().prec = 40
SIG_DIGITS = 20  # >= 17 significant digits, so every double round-trips

D65 = (F("0.3127"), F("0.3290"))

# name in the config -> ((xr, yr), (xg, yg), (xb, yb)), white
SPACES = {
    "Linear Rec.709 (sRGB)": (
        ((F("0.64"), F("0.33")), (F("0.30"), F("0.60")), (F("0.15"), F("0.06"))),
        D65),
    "Linear Rec.2020": (
        ((F("0.708"), F("0.292")), (F("0.170"), F("0.797")), (F("0.131"), F("0.046"))),
        D65),
    "Linear P3-D65": (
        ((F("0.680"), F("0.320")), (F("0.265"), F("0.690")), (F("0.150"), F("0.060"))),
        D65),
    "Linear Adobe RGB (1998)": (
        ((F("0.64"), F("0.33")), (F("0.21"), F("0.71")), (F("0.15"), F("0.06"))),
        D65),
}


def xy_to_XYZ(x, y):
    return [x / y, F(1), (1 - x - y) / y]


def det3(m):
    return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))


def solve3(m, v):
    """Cramer's rule, exact."""
    d = det3(m)
    out = []
    for c in range(3):
        mc = [row[:] for row in m]
        for r in range(3):
            mc[r][c] = v[r]
        out.append(det3(mc) / d)
    return out


def npm(primaries, white):
    cols = [xy_to_XYZ(*p) for p in primaries]
    P = [[cols[c][r] for c in range(3)] for r in range(3)]
    W = xy_to_XYZ(*white)
    S = solve3(P, W)
    return [[P[r][c] * S[c] for c in range(3)] for r in range(3)], W


def fmt(q):
    if q == 0:
        return "0"
    d = Decimal(q.numerator) / Decimal(q.denominator)
    s = format(d, ".%de" % (SIG_DIGITS - 1))
    mant, exp = s.split("e")
    e = int(exp)
    # plain notation for readability (values here are all in ~[1e-3, 2])
    return format(Decimal(mant).scaleb(e), "f") if -6 < e < 3 else s


def yaml_matrix(m):
    vals = []
    for r in range(3):
        vals += [fmt(m[r][0]), fmt(m[r][1]), fmt(m[r][2]), "0"]
    vals += ["0", "0", "0", "1"]
    return "matrix: [" + ", ".join(vals) + "]"


def main(argv):
    results = {name: npm(*spec) for name, spec in SPACES.items()}

    if len(argv) == 3 and argv[1] == "--check":
        text = open(argv[2], encoding="utf-8").read()
        ok = True
        for name, (m, _) in results.items():
            line = yaml_matrix(m)
            found = line in text
            print(("OK      " if found else "MISSING ") + name)
            ok &= found
        return 0 if ok else 1

    for name, (m, W) in results.items():
        print("# %s  (RGB -> CIE XYZ D65, white Y = 1)" % name)
        for r in range(3):
            print("#   [" + ", ".join("%s" % fmt(v) for v in m[r]) + "]")
        print("#   white XYZ = (" + ", ".join(fmt(v) for v in W) + ")")
        sums = [sum(m[r]) for r in range(3)]
        assert sums == W, "row sums must equal the white exactly"
        print("  " + yaml_matrix(m))
        print()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
