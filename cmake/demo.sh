#!/usr/bin/env bash
# make demo: spectralizes the paper's two examples and a few colours, printing a summary of each.
set -euo pipefail
build="${1:-build}"
bin="$build/spectralize"
out="$build/demo"
mkdir -p "$out"

summary() {  # summary NAME JSON-FILE: one line from spectralize's own JSON (one field per line)
  local name="$1" file="$2"
  field() { sed -n "s/^  \"$1\": \"\{0,1\}\([^\",]*\)\"\{0,1\},\{0,1\}$/\1/p" "$file" | head -1; }
  local values
  values=$(sed -n '/"values": \[/,/\]/p' "$file" | sed '1d;$d' | tr -d ' ,')
  printf '%-34s %-11s status=%-12s L=%6s K=%6s rel.err=%-8.1e min=%-10.4g max=%.4g\n' \
    "$name" "$(field mode)" "$(field status)" "$(field admissible)" "$(field dropped)" \
    "$(field relative_error)" "$(echo "$values" | sort -g | head -1)" \
    "$(echo "$values" | sort -g | tail -1)"
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
