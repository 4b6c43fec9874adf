#!/usr/bin/env bash
# The fixed cost of a USD stage: `spectralize ingest STAGE.usda -o OUT -q` on a small stage
# (an sRGB albedo, a raw normal map, a sky dome, a 3200 K key light, each texture a small
# file), first run (a fresh DESTDIR: three files converted) and rerun (all up to date), whole
# process, repeated; prints the wall time's minimum / median / maximum. Most of it is Python's
# and OpenUSD's start. With a second binary (an older build, its python/ module beside it),
# both run alternately and the ratio of the medians is printed.
# Usage: tests/bench/bench_usd_stage.sh [build-dir] [runs] [baseline-binary]
set -euo pipefail
build="$(readlink -f "${1:-build}")"
runs="${2:-5}"
baseline="${3:-}"
venv="${SPECTRALIZE_VENV:-$HOME/.cache/spectralize/venv}"
src="$(cd "$(dirname "$0")/../.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/shop/tex"
cp "$src/testimages/colorchecker_srgb8.png" "$work/shop/tex/albedo.png"
cp "$src/testimages/colorchecker_srgb8.png" "$work/shop/tex/normal.png"
cp "$src/testimages/hdri_sunset_256x128.exr" "$work/shop/tex/sky.exr"
"$venv/bin/python" - "$work/shop/shop.usda" <<'PY'
import sys
from pxr import Sdf, Usd, UsdLux, UsdShade
stage = Usd.Stage.CreateNew(sys.argv[1])
surface = UsdShade.Shader.Define(stage, "/World/Mat/Surface")
surface.CreateIdAttr("UsdPreviewSurface")
for name, space in (("diffuseColor", "sRGB"), ("normal", "raw")):
    tex = UsdShade.Shader.Define(stage, "/World/Mat/" + name)
    tex.CreateIdAttr("UsdUVTexture")
    tex.CreateInput("file", Sdf.ValueTypeNames.Asset).Set("tex/%s.png" % name.replace("diffuseColor", "albedo"))
    tex.CreateInput("sourceColorSpace", Sdf.ValueTypeNames.Token).Set(space)
    surface.CreateInput(name, Sdf.ValueTypeNames.Color3f).ConnectToSource(tex.ConnectableAPI(), "rgb")
UsdLux.DomeLight.Define(stage, "/World/Sky").CreateTextureFileAttr("tex/sky.exr")
key = UsdLux.RectLight.Define(stage, "/World/Key")
key.CreateEnableColorTemperatureAttr(True)
key.CreateColorTemperatureAttr(3200.0)
stage.Save()
PY

run_once() {  # binary fresh|rerun -> wall seconds
  local out="$work/out.$(basename "$(dirname "$1")")"
  [ "$2" = rerun ] || rm -rf "$out"
  TIMEFORMAT='%R'
  { time "$1" ingest "$work/shop/shop.usda" -o "$out" -q >/dev/null 2>"$work/err"; } 2>&1 || {
    cat "$work/err" >&2
    exit 1
  }
}
stats() { sort -g | awk '{v[NR] = $1} END {printf "%.3f / %.3f / %.3f s", v[1], v[int((NR + 1) / 2)], v[NR]}'; }
median() { sort -g | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }

"$build/spectralize" --version | head -1
echo "$(nproc) cores; $runs runs of each; wall time (min / median / max) of one stage"
for mode in fresh rerun; do
  : >"$work/new.txt"
  : >"$work/old.txt"
  for r in $(seq 1 "$runs"); do
    run_once "$build/spectralize" "$mode" >>"$work/new.txt"
    [ -z "$baseline" ] || run_once "$baseline" "$mode" >>"$work/old.txt"
  done
  printf '%6s: %s\n' "$mode" "$(stats <"$work/new.txt")"
  if [ -n "$baseline" ]; then
    printf '%6s  baseline: %s; ratio of medians (this / baseline) %.2f\n' "" "$(stats <"$work/old.txt")" \
      "$(awk -v a="$(median <"$work/new.txt")" -v b="$(median <"$work/old.txt")" 'BEGIN {print a / b}')"
  fi
done
