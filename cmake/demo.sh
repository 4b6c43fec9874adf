#!/usr/bin/env bash
# make demo: spectralizes the paper's two examples and a few colours, printing a summary of each.
set -euo pipefail
build="${1:-build}"
bin="$build/spectralize"
out="$build/demo"
mkdir -p "$out"

summary() {  # summary NAME JSON-FILE
  python3 - "$1" "$2" <<'PY'
import json, sys
name, path = sys.argv[1], sys.argv[2]
r = json.load(open(path))
v = r["values"]
print(f"{name:34s} {r['mode']:11s} status={r['status']:12s} L={r['admissible']:6d} "
      f"K={r['dropped']:6d} rel.err={r['relative_error']:.1e} "
      f"min={min(v):.4g} max={max(v):.4g}")
PY
}

run() {  # run NAME ARGS...
  local name="$1"; shift
  local file="$out/$(echo "$name" | tr ' ,()/' '_____').json"
  "$bin" "$@" --format json >"$file"
  summary "$name" "$file"
}

echo "spectralize demo: spectra in $out/*.json"
run "paper light (6000,5000,1000) lm" --color 6000,5000,1000
run "paper surface (0.21,0.72,0.15)" --color 0.21,0.72,0.15 --mode reflectance
run "white surface" --color 1,1,1 --mode reflectance
run "ACEScg red light" --color 1,0,0 --colorspace ACEScg
run "sRGB texel (200,30,40)/255" --color 0.784,0.118,0.157 --colorspace "sRGB - Texture" --mode reflectance
run "Rec.2020 green, out of gamut" --color 0,1,0 --colorspace "Linear Rec.2020" --mode reflectance 2>/dev/null
"$bin" --color 6000,5000,1000 >"$out/paper_light.csv"
echo "CSV of the paper's light: $out/paper_light.csv ($(wc -l <"$out/paper_light.csv") lines)"
