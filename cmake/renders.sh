#!/usr/bin/env bash
# make renders: the path tracer's measurements and figures (docs/RENDERERS.md) into OUTDIR. The
# inputs come from spectralize itself: the sRGB tables (spectralize table) and the spectral EXRs
# of the chart and the HDRI (the dense reference); then spectralize_path_tracer renders the
# convergence scene and the comparison under illuminant A (and D65 as a control).
# Usage: renders.sh BUILD_DIR OUTDIR
set -euo pipefail
build="$(realpath "$1")"
mkdir -p "$2"
out="$(realpath "$2")"
source="$(cd "$(dirname "$0")/.." && pwd)"
spz="$build/spectralize"
tracer="$build/spectralize_path_tracer"
in="$out/inputs"
mkdir -p "$in"
chart="$source/testimages/colorchecker_srgb16.png"
hdri="$source/testimages/hdri_forest_256x128.exr"

"$spz" table --colorspace "Linear Rec.709 (sRGB)" --mode reflectance -o "$in/srgb_reflectance.spztab" -q
"$spz" table --colorspace "Linear Rec.709 (sRGB)" --mode emission -o "$in/srgb_emission.spztab" -q
"$spz" "$chart" --colorspace "sRGB - Texture" --mode reflectance -d float -o "$in/chart.exr" -q
"$spz" "$hdri" --colorspace "Linear Rec.709 (sRGB)" --mode emission -d float -o "$in/hdri.exr" -q

"$tracer" convergence --texture "$chart" --environment "$hdri" \
  --reflectance-table "$in/srgb_reflectance.spztab" --emission-table "$in/srgb_emission.spztab" \
  --texture-spectra "$in/chart.exr" --environment-spectra "$in/hdri.exr" \
  --size 64 --spp 1,4,16,64,256 --json "$out/convergence.json"
for light in A D65; do
  prefix=()
  [ "$light" = A ] && prefix=(--png-prefix "$out/render_A")
  "$tracer" compare --texture "$chart" --environment "$hdri" \
    --reflectance-table "$in/srgb_reflectance.spztab" --illuminant "$light" \
    --sigmoid-resolution 64 --size 200 --spp 256 --json "$out/compare_$light.json" "${prefix[@]}"
done
