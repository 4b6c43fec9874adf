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
echo "The paper's examples (spectralize --color ...):"
for args in "6000,5000,1000" "0.21,0.72,0.15 --mode reflectance"; do
  # shellcheck disable=SC2086
  "$bin" --color $args --format json >"$out/color.json"
  printf '  --color %-36s status=%s L=%s K=%s relative error=%s\n' "$args" \
    "$(field status "$out/color.json")" "$(field admissible "$out/color.json")" \
    "$(field dropped "$out/color.json")" "$(field relative_error "$out/color.json")"
done
echo
echo "The same surface with the smooth model, and both plotted (spectralize --color ... -o PLOT):"
"$bin" --color 0.21,0.72,0.15 --mode reflectance --model smooth --format json >"$out/color.json"
printf '  --color %-36s status=%s relative error=%s\n' "0.21,0.72,0.15 --model smooth" \
  "$(field status "$out/color.json")" "$(field relative_error "$out/color.json")"
"$bin" --color 0.21,0.72,0.15 --mode reflectance -o "$out/surface_paper.png" -q
"$bin" --color 0.21,0.72,0.15 --mode reflectance --model smooth -o "$out/surface_smooth.png" -q
echo "  plots: $out/surface_paper.png, $out/surface_smooth.png"
echo "More: make figures (the paper's figures), make validate (ColorChecker metamerism table)."
