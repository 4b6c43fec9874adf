#!/usr/bin/env bash
# The folders of src/ depend one way (docs/DESIGN.md §1): each may include only the folders
# listed after it (and itself). Prints every include that points up or sideways; exit 1 if any.
# Usage: check_layers.sh SOURCE_DIR
set -euo pipefail
cd "$1/src"
declare -A allowed=(
  [core]="spectralize"
  [text]="spectralize core"
  [imagefile]="spectralize core text"
  [colour]="spectralize core text imagefile"
  [settings]="spectralize core text imagefile"
  [classify]="spectralize core text imagefile colour settings"
  [pipeline]="spectralize core text imagefile colour settings classify"
  [ingest]="spectralize core text imagefile colour settings classify pipeline"
  [plot]="spectralize core text imagefile colour settings"
  [baseline]="spectralize core"
  [rt_c]="spectralize"
)
bad=0
for dir in "${!allowed[@]}"; do
  [ -d "$dir" ] || { echo "check_layers: no folder src/$dir" >&2; bad=1; continue; }
  while IFS= read -r line; do
    file="${line%%:*}"
    target="$(sed -E 's/.*#include "([a-z_]+)\/.*/\1/' <<<"${line#*:}")"
    [ "$target" = "$dir" ] && continue
    case " ${allowed[$dir]} " in *" $target "*) ;; *)
      echo "src/$file includes $target/: $dir may include only ${allowed[$dir]}"; bad=1 ;;
    esac
  done < <(grep -rHE '^#include "[a-z_]+/' "$dir" --include='*.h' --include='*.cpp' || true)
done
# Inside core, by topic: each subfolder may include core's own files (core/*.h) and the
# subfolders listed after it.
declare -A core_allowed=(
  [colorimetry]=""
  [solvers]="colorimetry"
  [gamut]="colorimetry"
  [models]="colorimetry solvers"
  [tables]="colorimetry gamut"
)
for sub in "${!core_allowed[@]}"; do
  [ -d "core/$sub" ] || { echo "check_layers: no folder src/core/$sub" >&2; bad=1; continue; }
  while IFS= read -r line; do
    file="${line%%:*}"
    target="$(sed -E 's/.*#include "core\/([a-z_]+)\/.*/\1/' <<<"${line#*:}")"
    [ "$target" = "$sub" ] && continue
    case " ${core_allowed[$sub]} " in *" $target "*) ;; *)
      echo "src/$file includes core/$target/: core/$sub may include only ${core_allowed[$sub]:-nothing else}"; bad=1 ;;
    esac
  done < <(grep -rHE '^#include "core/[a-z_]+/' "core/$sub" || true)
done
for sub in core/*/; do
  sub="${sub#core/}"; sub="${sub%/}"
  [ -n "${core_allowed[$sub]+x}" ] || { echo "src/core/$sub/ is not in the core layer table"; bad=1; }
done
# No folder of src/ holds more than 15 translation units: a folder is one topic.
while IFS= read -r dir; do
  n=$(find "$dir" -maxdepth 1 -name '*.cpp' | wc -l)
  [ "$n" -le 15 ] || { echo "src/$dir holds $n sources (more than 15): split it by topic"; bad=1; }
done < <(find . -mindepth 1 -type d | sed 's#^\./##')
# Every folder of src/ is in the table above or a front end (tool, figures, path_tracer).
for dir in */; do
  dir="${dir%/}"
  case "$dir" in tool|figures|path_tracer) continue ;; esac
  [ -n "${allowed[$dir]+x}" ] || { echo "src/$dir/ is not in the layer table"; bad=1; }
done
exit $bad
