#!/usr/bin/env bash
# spectralize as a subproject (add_subdirectory): configure a parent project, build only the
# core library and a program that uses it (Debug: quick), run the program.
# Usage: tests/install/subproject_test.sh SOURCE_DIR
set -euo pipefail
source="$(readlink -f "$1")"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cmake -S "$source/tests/install/subproject" -B "$work" -DSPECTRALIZE_SOURCE="$source" \
  -DCMAKE_BUILD_TYPE=Debug >/dev/null
cmake --build "$work" --target consumer -j 2 >/dev/null
"$work/consumer" "$source/data/cie1931_2deg_cmf_1nm.csv"
echo "subproject build passed"
