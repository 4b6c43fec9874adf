#!/usr/bin/env bash
# Whole-process timings of the CLI (make bench): spectralize on the 1024x512 HDRI at 5 nm
# against oiiotool reading the same input and writing a file with the same number of channels
# (3 + 81 = 84, HALF, ZIP), measured in the same run; then the cache's time to first result.
# Usage: tests/bench/bench_cli.sh [build-dir] [runs]
set -euo pipefail
build="${1:-build}"
runs="${2:-5}"
bin="$build/spectralize"
input="testimages/hdri_interior_1024x512.exr"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Median wall time of a command over $runs runs, in seconds.
median() {
  local times=()
  for _ in $(seq "$runs"); do
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >/dev/null 2>&1
    t1=$(date +%s.%N)
    times+=("$(echo "$t1 - $t0" | bc -l)")
  done
  printf '%s\n' "${times[@]}" | sort -g | sed -n "$(( (runs + 1) / 2 ))p"
}

# oiiotool writes R,G,B plus 81 more channels made from them. Copies of R, G, B would compress
# to almost nothing (3 MB instead of ~40 MB: zlib finds the repeats), so each extra channel is
# also scaled by its own factor, giving data of the same size and entropy as real spectra. The
# plain-copy variant is timed too, for reference.
channels="R,G,B"
factors="1,1,1"
for i in $(seq 0 80); do
  case $(( i % 3 )) in 0) c=R ;; 1) c=G ;; *) c=B ;; esac
  channels="$channels,c$i=$c"
  factors="$factors,$(echo "1 + $i / 97" | bc -l | cut -c1-6)"
done

echo "input: $input ($(oiiotool --info "$input" | head -1 | sed 's/.*: *//'))"
t_oiio=$(median oiiotool "$input" --ch "$channels" --mulc "$factors" -d half --compression zip -o "$work/oiio.exr")
t_copy=$(median oiiotool "$input" --ch "$channels" -d half --compression zip -o "$work/copy.exr")
t_spec=$(median "$bin" "$input" -o "$work/spec.exr" -q)
t_smooth=$(median "$bin" "$input" -o "$work/smooth.exr" -q --model smooth)
printf 'oiiotool read + write 84 channels (half, zip):   %.3f s, %s bytes (median of %d)\n' "$t_oiio" "$(stat -c %s "$work/oiio.exr")" "$runs"
printf '  (same with plain copies of R,G,B:              %.3f s, %s bytes)\n' "$t_copy" "$(stat -c %s "$work/copy.exr")"
printf 'spectralize, RGB + 81 bands (half, zip):         %.3f s, %s bytes (median of %d)\n' "$t_spec" "$(stat -c %s "$work/spec.exr")" "$runs"
printf 'ratio spectralize / oiiotool:                     %.2f (target <= 1.3)\n' "$(echo "$t_spec / $t_oiio" | bc -l)"
printf 'spectralize --model smooth:                       %.3f s (ratio %.2f)\n' "$t_smooth" "$(echo "$t_smooth / $t_oiio" | bc -l)"

# Spectral synthesis alone with a warm cache: convert seconds from the report, one thread.
"$bin" "$input" -o "$work/warm.exr" -q --threads 1 --cache "$work/cache" --report "$work/cold.json"
"$bin" "$input" -o "$work/warm.exr" -q --threads 1 --cache "$work/cache" --report "$work/warm.json"
echo "cache, 1 thread: $(grep -o '"convert": [0-9.e-]*' "$work/cold.json") s cold, $(grep -o '"convert": [0-9.e-]*' "$work/warm.json") s warm (read + OCIO + table + measure, 524288 pixels)"

# Time to first result: the whole job with an empty cache, then with the cache it left.
for grid in 380:780:5 380:780:1; do
  t_cold=$(median bash -c "rm -rf '$work/c' && '$bin' '$input' -o '$work/g.exr' -q --wavelengths $grid --cache '$work/c'")
  t_warm=$(median "$bin" "$input" -o "$work/g.exr" -q --wavelengths "$grid" --cache "$work/c")
  printf 'grid %-10s empty cache: %.2f s; with the cache of a previous run: %.2f s\n' "$grid" "$t_cold" "$t_warm"
done
