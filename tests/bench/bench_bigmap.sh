#!/usr/bin/env bash
# Big environment maps (make bench): 4096x2048 and 8192x4096 maps made at run time from the
# 1024x512 HDRI (nothing committed), converted at 5 nm to half/zip. Per size: wall time with
# --threads 1 and --threads 2 in the same run (the speedup), peak RSS, minor page faults and the
# kernel's share of CPU time; at 4K the same 84-channel content re-encoded by oiiotool (the
# baseline ratio) and a table of time against size for compression codecs and zip levels.
# BIGMAP_16K=1 adds a 16384x8192 map, --threads 2 only (about 4 minutes, 3.7 GB written), for
# its peak RSS (target <= 1 GB).
# Usage: tests/bench/bench_bigmap.sh [build-dir]
set -euo pipefail
build="${1:-build}"
bin="$build/spectralize"
source_map="testimages/hdri_interior_1024x512.exr"
work="$(mktemp -d "${TMPDIR:-/tmp}/bench_bigmap.XXXXXX")"
trap 'rm -rf "$work"' EXIT

# Runs a command under GNU time; prints "wall user sys maxrss_kb minor_faults".
measure() {
  /usr/bin/time -f "%e %U %S %M %R" -o "$work/time.txt" "$@" >/dev/null 2>&1
  cat "$work/time.txt"
}

# One line per run: label, wall, RSS, minor faults, kernel share of CPU, size written.
report() {
  local label="$1" out="$2"
  read -r wall user sys rss faults <<<"$3"
  printf '%-34s %7.2f s  %5d MB RSS  %8d minflt  kernel %4.1f%% of CPU  %6d MB\n' "$label" \
    "$wall" $((rss / 1024)) "$faults" "$(echo "100 * $sys / ($user + $sys)" | bc -l)" \
    $(($(stat -c %s "$out") / 1000000))
}

sizes=(4096x2048 8192x4096)
[ "${BIGMAP_16K:-0}" = 1 ] && sizes+=(16384x8192)
for size in "${sizes[@]}"; do
  map="$work/map_$size.exr"
  oiiotool "$source_map" --resize "$size" -d half --compression zip -o "$map"
  echo "== $size, 5 nm, half, zip (default level), empty cache"
  declare -A wall=()
  thread_counts=(1 2)
  [ "$size" = 16384x8192 ] && thread_counts=(2)
  for threads in "${thread_counts[@]}"; do
    rm -rf "$work/cache"
    m=$(measure "$bin" "$map" -o "$work/out.exr" -q --threads "$threads" --cache "$work/cache")
    report "--threads $threads" "$work/out.exr" "$m"
    wall[$threads]=$(echo "$m" | cut -d' ' -f1)
  done
  [ -n "${wall[1]:-}" ] && printf 'speedup --threads 2 / --threads 1: %.2f (target >= 1.7)\n' \
    "$(echo "${wall[1]} / ${wall[2]}" | bc -l)"
  if [ "$size" = 4096x2048 ]; then
    m=$(measure oiiotool "$work/out.exr" -d half --compression zip -o "$work/copy.exr")
    report "oiiotool re-encodes the output" "$work/copy.exr" "$m"
    printf 'ratio spectralize (2 threads) / oiiotool re-encode: %.2f (target <= 0.6)\n' \
      "$(echo "${wall[2]} / $(echo "$m" | cut -d' ' -f1)" | bc -l)"
    echo "-- compression: time against size (--threads 2, warm cache)"
    for c in zip:1 zip:2 zip:4 zip:6 zips:1 zips:4 piz pxr24 rle none; do
      m=$(measure "$bin" "$map" -o "$work/c.exr" -q --compression "$c" --cache "$work/cache")
      report "--compression $c" "$work/c.exr" "$m"
    done
    rm -f "$work/copy.exr" "$work/c.exr"
  fi
  rm -f "$map" "$work/out.exr"
done
