#!/usr/bin/env bash
# The cost of a file beyond its pixels: `spectralize ingest DIR -o OUT -q --jobs 1` over N
# copies of one 8x8 8-bit PNG (300 and 3,000 by default), whole process, repeated; prints the
# CPU (user + system) and wall time per file, the process start included, as the minimum,
# median and maximum of the runs. With a second binary (an older build), both are run
# alternately on the same files and the ratio of the medians is printed.
# Usage: tests/bench/bench_tiny_files.sh [build-dir] [runs] [baseline-binary]
set -euo pipefail
build="$(readlink -f "${1:-build}")"
runs="${2:-5}"
baseline="${3:-}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
counts=(${SPECTRALIZE_BENCH_FILES:-300 3000})

# One run: "cpu_seconds wall_seconds" of the whole process (bash's own accounting).
run_once() {  # binary folder
  local out="$work/out" t
  rm -rf "$out"
  TIMEFORMAT='%U %S %R'
  t=$({ time "$1" ingest "$2" -o "$out" -q --jobs 1 >/dev/null 2>"$work/err"; } 2>&1) || {
    cat "$work/err" >&2
    exit 1
  }
  awk '{printf "%.4f %.4f\n", $1 + $2, $3}' <<<"$t"
}

# min / median / max of a column of numbers, per file, in ms.
stats() {  # files
  sort -g | awk -v n="$1" '{v[NR] = $1 * 1000 / n} END {printf "%.2f / %.2f / %.2f", v[1], v[int((NR + 1) / 2)], v[NR]}'
}
median() {
  sort -g | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN {printf "%.4f", a / b}'; }

"$build/spectralize" --version | head -1
echo "$(nproc) cores; $runs runs of each; ms per file (min / median / max), the process start included"
for n in "${counts[@]}"; do
  dir="$work/tiny$n"
  mkdir -p "$dir"
  oiiotool --pattern constant:color=0.3,0.5,0.7 8x8 3 -d uint8 -o "$dir/t0.png"
  for i in $(seq 1 $((n - 1))); do cp "$dir/t0.png" "$dir/t$i.png"; done
  : >"$work/new.txt"
  : >"$work/old.txt"
  for r in $(seq 1 "$runs"); do
    run_once "$build/spectralize" "$dir" >>"$work/new.txt"
    [ -z "$baseline" ] || run_once "$baseline" "$dir" >>"$work/old.txt"
  done
  printf '%6d files: CPU %s ms, wall %s ms\n' "$n" "$(cut -d' ' -f1 "$work/new.txt" | stats "$n")" \
    "$(cut -d' ' -f2 "$work/new.txt" | stats "$n")"
  if [ -n "$baseline" ]; then
    printf '%6s baseline: CPU %s ms, wall %s ms\n' "" "$(cut -d' ' -f1 "$work/old.txt" | stats "$n")" \
      "$(cut -d' ' -f2 "$work/old.txt" | stats "$n")"
    printf '%6s ratio of medians (this / baseline): CPU %.2f, wall %.2f\n' "" \
      "$(ratio "$(cut -d' ' -f1 "$work/new.txt" | median)" "$(cut -d' ' -f1 "$work/old.txt" | median)")" \
      "$(ratio "$(cut -d' ' -f2 "$work/new.txt" | median)" "$(cut -d' ' -f2 "$work/old.txt" | median)")"
  fi
  rm -rf "$dir"
done
