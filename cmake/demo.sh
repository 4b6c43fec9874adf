#!/usr/bin/env bash
# make demo: spectralizes every file in testimages/ into build/demo/ and prints a summary of each
# report, then the paper's two example colours.
set -euo pipefail
build="${1:-build}"
bin="$build/spectralize"
out="$build/demo"
mkdir -p "$out"

# A field of a report (our own JSON: one "key": value per line).
field() { sed -n "s/^  \"$1\": \"\{0,1\}\([^\",]*\)\"\{0,1\},\{0,1\}$/\1/p" "$2" | head -1; }

echo "spectralize demo: testimages/* -> $out/*.exr (reports: $out/*.json)"
printf '%-32s %-11s %-22s %9s %8s %7s %9s %7s\n' file mode colorspace pixels "out-gam" invalid "max err" seconds
for f in testimages/*.exr testimages/*.hdr testimages/*.png; do
  name=$(basename "$f")
  "$bin" "$f" -o "$out/${name%.*}.exr" --report "$out/${name%.*}.json" -q
  r="$out/${name%.*}.json"
  printf '%-32s %-11s %-22s %9s %8s %7s %9.1e %7.2f\n' "$name" "$(field mode "$r")" \
    "$(field colorspace "$r")" "$(field pixels "$r")" "$(field out_of_gamut_pixels "$r")" \
    "$(field invalid_pixels "$r")" "$(field max_relative_xyz_error "$r")" \
    "$(sed -n 's/^    "total": \([0-9.e-]*\)$/\1/p' "$r")"
done
echo "(max err: relative XYZ error of the written HALF samples; use --format float for ~1e-7)"
echo
echo "The paper's examples by each model (spectralize --color ... --model M):"
for model in natural smooth paper; do
  for args in "6000,5000,1000" "0.21,0.72,0.15 --mode reflectance"; do
    # shellcheck disable=SC2086
    "$bin" --color $args --model "$model" --format json >"$out/color.json"
    printf '  --color %-34s --model %-8s status=%s relative error=%s\n' "$args" "$model" \
      "$(field status "$out/color.json")" "$(field relative_error "$out/color.json")"
  done
  "$bin" --color 0.21,0.72,0.15 --mode reflectance --model "$model" -o "$out/surface_$model.png" -q
done
echo "  plots of the surface: $out/surface_natural.png, surface_smooth.png, surface_paper.png"
echo
# The guide's Mitsuba 3 scene (docs/examples/mitsuba_scene.py): an albedo texture through
# spectralize_rgb and spectral_bitmap, a spectralized HDRI through spectral_envmap.
venv="${SPECTRALIZE_VENV:-${HOME:-/root}/.cache/spectralize/venv}"
llvm=$(ls /usr/lib/*/libLLVM.so.19* 2>/dev/null | head -1)
if [ -x "$venv/bin/python" ] && [ -n "$llvm" ] && ls "$build"/python/spectralize*.so >/dev/null 2>&1; then
  echo "In Mitsuba 3 (llvm_ad_spectral), the guide's scene:"
  PYTHONPATH="$build/python" DRJIT_LIBLLVM_PATH="$llvm" SPECTRALIZE_EXE="$bin" \
    SPECTRALIZE_CACHE="$out/mitsuba_cache" \
    "$venv/bin/python" docs/examples/mitsuba_scene.py "$out/mitsuba_scene.png" 16 | sed 's/^/  /'
  echo "  picture: $out/mitsuba_scene.png (docs/guide/mitsuba.md)"
else
  echo "Mitsuba 3 is not set up (make demo installs it): its scene is left out."
fi
echo "More: make figures (the paper's figures), make validate (metamerism on measured reflectances)."
