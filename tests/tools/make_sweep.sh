#!/usr/bin/env bash
# Builds the two small float colour-sweep EXRs in testimages/ with oiiotool only:
#   sweep_acescg_64x32.exr    tagged as ACEScg
#   sweep_rec2020_64x32.exr   tagged as Linear Rec.2020
# Both hold the SAME pixel values (RGB triples); only the colour-space tag differs.
#
# Layout (64 x 32, RGB, 32-bit float, ZIP), x = column, y = row:
#   columns 0..59: hue H(x) around the primaries, 6 segments of 10 px, linear in RGB:
#       R(1,0,0) -> Y(1,1,0) -> G(0,1,0) -> C(0,1,1) -> B(0,0,1) -> M(1,0,1) -> (R)
#       H(10k + i) = lerp(P_k, P_k+1, i/10); x = 0,10,20,30,40,50 are exactly R,Y,G,C,B,M.
#     pixel = g + s(y) * (H(x) - g)    (g = grey level of the band)
#     rows  0.. 8  g = 1,    s = 0, 1/8, ..., 1    white (1,1,1) at row 0 -> exact hues at row 8
#     rows  9..15  g = 1,    s = 1.05, 1.10, ..., 1.35
#                  beyond the primaries: components 1-s = -0.05 ... -0.35 (row 9 is the
#                  "small negative component" row: e.g. (1,-0.05,-0.05))
#     rows 16..23  g = 0,    s = 0.25, 0.50, ..., 2.00   (row 19 = exact hues, row 23 = 2*H)
#     rows 24..31  g = 0.18, s = 0, 1/7, ..., 1          (mid grey -> exact hues at row 31)
#   column 60: black (0,0,0)       column 61: white (1,1,1)
#   column 62: bright white (4,4,4) column 63: neutral ramp 0.0, 0.1, ..., 3.1 (top to bottom)
#
# Colour-space metadata: OIIO 2.4's OpenEXR writer does NOT store "oiio:*" attributes
# (so `--attrib oiio:ColorSpace ACEScg` is silently dropped, and on reading OIIO reports
# oiio:ColorSpace "Linear" for every EXR). The space is therefore recorded with
#   chromaticities  (standard OpenEXR attribute, type chromaticities)
#   colorInteropID  (string; Color Interop Forum ID: lin_ap1_scene / lin_rec2020_scene)
# and oiio:ColorSpace is still set, so that an OIIO that does write it will store it.
set -euo pipefail

REPO_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "${REPO_ROOT}/testimages"

# fill:left/right and fill:top/bottom gradients include both end points: u = x/(w-1).
# "A B --paste +x+y" pastes A (pushed first) into B (top of stack), so every paste
# below is preceded by --swap: the canvas is pushed first, the piece on top of it.
seg() {  # seg FROM TO -> 11-px gradient cut to its first 10 px (u = i/10)
    echo --pattern "fill:left=$1:right=$2" 11x32 3 --cut 10x32+0+0
}
band() {  # band Y0 H G S_TOP S_BOTTOM -> g + s*(hue - g) for rows Y0..Y0+H-1
    echo hue --cut "60x$2+0+$1" --subc "$3" \
         --pattern "fill:top=$4,$4,$4:bottom=$5,$5,$5" "60x$2" 3 --mul --addc "$3" \
         --swap --paste "+0+$1"
}

# shellcheck disable=SC2046
build=(
    --create 60x32 3
    $(seg 1,0,0 1,1,0) --swap --paste +0+0
    $(seg 1,1,0 0,1,0) --swap --paste +10+0
    $(seg 0,1,0 0,1,1) --swap --paste +20+0
    $(seg 0,1,1 0,0,1) --swap --paste +30+0
    $(seg 0,0,1 1,0,1) --swap --paste +40+0
    $(seg 1,0,1 1,0,0) --swap --paste +50+0
    --label hue --pop
    --create 64x32 3
    $(band 0 9 1 0 1)
    $(band 9 7 1 1.05 1.35)
    $(band 16 8 0 0.25 2)
    $(band 24 8 0.18 0 1)
    --pattern constant:color=0,0,0 1x32 3 --swap --paste +60+0
    --pattern constant:color=1,1,1 1x32 3 --swap --paste +61+0
    --pattern constant:color=4,4,4 1x32 3 --swap --paste +62+0
    --pattern fill:top=0,0,0:bottom=3.1,3.1,3.1 1x32 3 --swap --paste +63+0
    --label sweep
)

oiiotool --nosoftwareattrib "${build[@]}" \
    --attrib oiio:ColorSpace ACEScg \
    --attrib colorInteropID lin_ap1_scene \
    --attrib:type=float[8] chromaticities 0.713,0.293,0.165,0.830,0.128,0.044,0.32168,0.33767 \
    -d float --compression zip -o sweep_acescg_64x32.exr

oiiotool --nosoftwareattrib "${build[@]}" \
    --attrib oiio:ColorSpace "Linear Rec.2020" \
    --attrib colorInteropID lin_rec2020_scene \
    --attrib:type=float[8] chromaticities 0.708,0.292,0.170,0.797,0.131,0.046,0.3127,0.3290 \
    -d float --compression zip -o sweep_rec2020_64x32.exr

for f in sweep_acescg_64x32.exr sweep_rec2020_64x32.exr; do
    iinfo -v --stats "$f"
done
