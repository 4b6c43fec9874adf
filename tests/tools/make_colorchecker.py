#!/usr/bin/env python3
"""Render the 24-patch ColorChecker (N. Ohta reflectances) as small sRGB PNG test images.

Plain Python 3 (no numpy). Writes, into testimages/ (or the directory given as argv[1]):

  colorchecker_srgb8.png       110x74, 8-bit RGB       (PNG colour type 2), sRGB chunk
  colorchecker_srgb8_rgba.png  110x74, 8-bit RGBA      (PNG colour type 6), sRGB chunk,
                               alpha 255 in patches, 128 in the gutter
  colorchecker_srgb16.png      110x74, 16-bit RGB      (PNG colour type 2), sRGB chunk,
                               same sRGB-encoded values as the 8-bit chart, quantised to 16 bit
  grey_ramp8.png               64x8,   8-bit grey      (PNG colour type 0), NO colour chunk,
                               column x has value round(x*255/63), i.e. 0..255

Colour pipeline for each patch:
  * reflectance (5 nm, 380-780 nm) linearly interpolated to 1 nm, 0 outside 380-780 nm;
  * XYZ under CIE D65 (1 nm table) with the CIE 1931 2 deg observer (1 nm table),
    trapezoid rule over the CMF table's range (360-830 nm), normalised so that a
    perfect reflector (reflectance 1 at every wavelength of that range) has Y = 1;
  * XYZ -> linear sRGB with the inverse (computed here) of the Rec.709/D65 RGB->XYZ matrix;
  * clip to [0, 1] (clipped patches are reported), sRGB-encode (IEC 61966-2-1), round.

Prints a table (patch name, linear sRGB, 8-bit and 16-bit codes) on stdout.
"""
import csv
import os
import struct
import sys
import zlib

REPO_ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
DATA = os.path.join(REPO_ROOT, "data")

RGB_TO_XYZ = [
    [0.41239079926595948, 0.35758433938387796, 0.18048078840183429],
    [0.21263900587151036, 0.71516867876775593, 0.07219231536073372],
    [0.01933081871559185, 0.11919477979462599, 0.95053215224966058],
]

PATCH = 16  # patch size in px
GUTTER = 2  # black border/gutter in px
COLS, ROWS = 6, 4


# ----------------------------------------------------------------------------- data
def read_table(path):
    """Return (header, rows) with rows as lists of floats."""
    with open(path, newline="") as f:
        r = csv.reader(f)
        header = next(r)
        rows = [[float(v) for v in row] for row in r if row]
    return header, rows


def load_1nm(path):
    """1 nm table -> (dict wavelength(int) -> tuple of values)."""
    _, rows = read_table(path)
    out = {}
    for row in rows:
        wl = row[0]
        assert abs(wl - round(wl)) < 1e-9, path
        out[int(round(wl))] = tuple(row[1:])
    return out


def interp_reflectance(wls5, values, wl):
    """Linear interpolation of a 5 nm reflectance curve at integer wl; 0 outside."""
    lo, hi = wls5[0], wls5[-1]
    if wl < lo or wl > hi:
        return 0.0
    i = (wl - lo) // 5
    w0 = wls5[i]
    if w0 == wl or i + 1 >= len(wls5):
        return values[i]
    t = (wl - w0) / (wls5[i + 1] - w0)
    return values[i] * (1.0 - t) + values[i + 1] * t


# ----------------------------------------------------------------------------- colour
def trapezoid(wls, f):
    """Trapezoid rule over consecutive samples (1 nm spacing here)."""
    s = 0.0
    for a, b in zip(wls[:-1], wls[1:]):
        s += 0.5 * (f(a) + f(b)) * (b - a)
    return s


def inv3(m):
    (a, b, c), (d, e, f), (g, h, i) = m
    det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
    return [
        [(e * i - f * h) / det, (c * h - b * i) / det, (b * f - c * e) / det],
        [(f * g - d * i) / det, (a * i - c * g) / det, (c * d - a * f) / det],
        [(d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det],
    ]


def mat_vec(m, v):
    return [sum(m[r][k] * v[k] for k in range(3)) for r in range(3)]


def srgb_encode(v):
    """IEC 61966-2-1 sRGB transfer function (input already clipped to [0,1])."""
    if v <= 0.0031308:
        return 12.92 * v
    return 1.055 * v ** (1.0 / 2.4) - 0.055


# ----------------------------------------------------------------------------- PNG
def _chunk(tag, data):
    body = tag + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


def write_png(path, width, height, channels, bitdepth, pixels, srgb_chunk=True):
    """Write a non-interlaced PNG.

    pixels: flat list, row-major, `channels` samples per pixel, integer samples in
    [0, 2**bitdepth - 1]. channels 1/3/4 -> colour type 0/2/6; bitdepth 8 or 16.
    """
    colour_type = {1: 0, 3: 2, 4: 6}[channels]
    assert bitdepth in (8, 16)
    assert len(pixels) == width * height * channels
    maxv = (1 << bitdepth) - 1
    raw = bytearray()
    row_len = width * channels
    for y in range(height):
        raw.append(0)  # filter type 0 (None)
        row = pixels[y * row_len:(y + 1) * row_len]
        for v in row:
            assert 0 <= v <= maxv
        if bitdepth == 8:
            raw += bytes(row)
        else:
            raw += struct.pack(">%dH" % row_len, *row)
    png = b"\x89PNG\r\n\x1a\n"
    png += _chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, bitdepth, colour_type, 0, 0, 0))
    if srgb_chunk:
        png += _chunk(b"sRGB", bytes([0]))  # rendering intent 0 = perceptual
    png += _chunk(b"IDAT", zlib.compress(bytes(raw), 9))
    png += _chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


# ----------------------------------------------------------------------------- main
def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else os.path.join(REPO_ROOT, "testimages")
    os.makedirs(out_dir, exist_ok=True)

    header, refl_rows = read_table(os.path.join(DATA, "colorchecker_n_ohta_5nm.csv"))
    names = header[1:]
    assert len(names) == 24, names
    wls5 = [int(round(r[0])) for r in refl_rows]
    assert wls5[0] == 380 and wls5[-1] == 780 and all(b - a == 5 for a, b in zip(wls5, wls5[1:]))
    curves = [[r[1 + p] for r in refl_rows] for p in range(24)]

    cmf = load_1nm(os.path.join(DATA, "cie1931_2deg_cmf_1nm.csv"))
    d65 = load_1nm(os.path.join(DATA, "cie_illuminant_d65_1nm.csv"))
    wls = sorted(w for w in cmf if w in d65)  # 360..830 nm, 1 nm
    assert all(b - a == 1 for a, b in zip(wls, wls[1:]))
    S = {w: d65[w][0] for w in wls}

    k = 1.0 / trapezoid(wls, lambda w: S[w] * cmf[w][1])
    xyz_to_rgb = inv3(RGB_TO_XYZ)

    patches = []  # (name, XYZ, linear rgb (unclipped), clipped flags, code8, code16)
    clipped = []
    for name, curve in zip(names, curves):
        R = {w: interp_reflectance(wls5, curve, w) for w in wls}
        XYZ = [k * trapezoid(wls, lambda w, c=c: R[w] * S[w] * cmf[w][c]) for c in range(3)]
        rgb = mat_vec(xyz_to_rgb, XYZ)
        clip = [min(max(v, 0.0), 1.0) for v in rgb]
        if clip != rgb:
            clipped.append((name, rgb))
        enc = [srgb_encode(v) for v in clip]
        code8 = [int(round(v * 255.0)) for v in enc]
        code16 = [int(round(v * 65535.0)) for v in enc]
        patches.append((name, XYZ, rgb, code8, code16))

    # ---- table
    print("Normalisation k = 1 / sum(D65 * ybar) = %.10g  (wavelengths %d..%d nm, 1 nm, trapezoid)"
          % (k, wls[0], wls[-1]))
    print("XYZ->linear sRGB matrix (inverse of the given RGB->XYZ):")
    for row in xyz_to_rgb:
        print("  [% .14f, % .14f, % .14f]" % tuple(row))
    print()
    print("| # | patch | X | Y | Z | linear sRGB (unclipped) | sRGB 8-bit | sRGB 16-bit |")
    print("|---|---|---|---|---|---|---|---|")
    for i, (name, XYZ, rgb, c8, c16) in enumerate(patches):
        print("| %d | %s | %.5f | %.5f | %.5f | %.5f, %.5f, %.5f | %d, %d, %d | %d, %d, %d |"
              % ((i + 1, name) + tuple(XYZ) + tuple(rgb) + tuple(c8) + tuple(c16)))
    print()
    if clipped:
        print("Patches clipped to [0,1] before encoding:")
        for name, rgb in clipped:
            print("  %s: linear sRGB = (%.6f, %.6f, %.6f)" % ((name,) + tuple(rgb)))
    else:
        print("No patch needed clipping.")

    # ---- images
    W = COLS * PATCH + (COLS + 1) * GUTTER
    H = ROWS * PATCH + (ROWS + 1) * GUTTER

    def patch_at(x, y):
        """Index of the patch covering (x, y), or None for the gutter."""
        px, ox = divmod(x - GUTTER, PATCH + GUTTER)
        py, oy = divmod(y - GUTTER, PATCH + GUTTER)
        if x < GUTTER or y < GUTTER or ox >= PATCH or oy >= PATCH or px >= COLS or py >= ROWS:
            return None
        return py * COLS + px

    rgb8, rgba8, rgb16 = [], [], []
    for y in range(H):
        for x in range(W):
            p = patch_at(x, y)
            if p is None:
                rgb8 += [0, 0, 0]
                rgba8 += [0, 0, 0, 128]
                rgb16 += [0, 0, 0]
            else:
                c8, c16 = patches[p][3], patches[p][4]
                rgb8 += c8
                rgba8 += c8 + [255]
                rgb16 += c16
    write_png(os.path.join(out_dir, "colorchecker_srgb8.png"), W, H, 3, 8, rgb8)
    write_png(os.path.join(out_dir, "colorchecker_srgb8_rgba.png"), W, H, 4, 8, rgba8)
    write_png(os.path.join(out_dir, "colorchecker_srgb16.png"), W, H, 3, 16, rgb16)

    RW, RH = 64, 8
    ramp = [int(round(x * 255.0 / (RW - 1))) for _ in range(RH) for x in range(RW)]
    write_png(os.path.join(out_dir, "grey_ramp8.png"), RW, RH, 1, 8, ramp, srgb_chunk=False)
    print()
    print("Wrote %dx%d charts and %dx%d grey ramp to %s" % (W, H, RW, RH, out_dir))


if __name__ == "__main__":
    main()
