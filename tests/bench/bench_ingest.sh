#!/usr/bin/env bash
# Batch ingest against a shell loop of single-file calls producing the same outputs, on a
# library generated here (about 200 files, 256^2 to 2048^2: 8/16-bit PNG, JPEG, half EXR,
# tiled .tx; about a quarter named as data maps), all in one run; then an up-to-date rerun.
# Usage: tests/bench/bench_ingest.sh [build-dir] [files]
set -euo pipefail
build="$(readlink -f "${1:-build}")"
files="${2:-200}"
bin="$build/spectralize"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
lib="$work/lib"
mkdir -p "$lib"

# Sizes: most textures small, some large, as in a real library.
size_of() {
  case $(( $1 % 20 )) in
    0) echo 2048 ;; 1|2) echo 1024 ;; 3|4|5|6|7|8) echo 512 ;; *) echo 256 ;;
  esac
}
echo "generating $files files in $lib ..."
for i in $(seq 0 $(( files - 1 ))); do
  s=$(size_of "$i")
  dir="$lib/set$(( i % 7 ))"
  mkdir -p "$dir"
  # A smooth gradient of four random colours with a little grain: the colour statistics of a
  # real texture (few distinct hues, compressible), not white noise.
  c() { awk -v s="$1" 'BEGIN { srand(s); printf "%.3f,%.3f,%.3f", 0.1 + 0.8 * rand(), 0.1 + 0.8 * rand(), 0.1 + 0.8 * rand() }'; }
  noise="--pattern fill:topleft=$(c $((i * 4))):topright=$(c $((i * 4 + 1))):bottomleft=$(c $((i * 4 + 2))):bottomright=$(c $((i * 4 + 3))) ${s}x${s} 3 --pattern noise:type=gaussian:mean=0:stddev=0.02:seed=$i ${s}x${s} 3 --add"
  case $(( i % 8 )) in
    0|1) oiiotool $noise -d uint8 -o "$dir/asset${i}_normal.png" ;;              # data map
    2) oiiotool $noise -d uint8 -o "$dir/asset${i}_albedo.png" ;;
    3) oiiotool $noise -d uint16 -o "$dir/asset${i}_basecolor.png" ;;
    4) oiiotool $noise -d uint8 -o "$dir/asset${i}_diffuse.jpg" ;;
    5) oiiotool $noise --mulc 4 -d half -o "$dir/asset${i}_env.exr" ;;
    6) oiiotool $noise --mulc 4 -d half --tile 64 64 -o "$dir/asset${i}_sky.tx" ;;
    7) oiiotool $noise -d uint8 -o "$dir/asset${i}_color.png" ;;
  esac
done
pixels=$(find "$lib" -type f | grep -v _normal | while read -r f; do oiiotool --info "$f" | sed -E 's/.*: *([0-9]+) x +([0-9]+).*/\1 \2/'; done | awk '{s += $1 * $2} END {print s}')
colour=$(find "$lib" -type f | grep -vc _normal)
echo "library: $files files, $colour colour files, $(( pixels / 1000000 )) Mpixel to convert"

now() { date +%s.%N; }
# The loop: one process per colour file, the data maps left out as ingest does.
t0=$(now)
find "$lib" -type f | grep -v _normal | while read -r f; do
  rel="${f#$lib/}"
  mkdir -p "$work/loop/$(dirname "$rel")"
  "$bin" "$f" -o "$work/loop/${rel%.*}.exr" -q
done
t_loop=$(echo "$(now) - $t0" | bc -l)
t0=$(now); "$bin" ingest "$lib" -o "$work/one" -q --jobs 1; t_one=$(echo "$(now) - $t0" | bc -l)
/usr/bin/time -f "%e %M" -o "$work/time.txt" "$bin" ingest "$lib" -o "$work/two" -q --jobs 2
read -r t_two rss_two <"$work/time.txt"
t0=$(now); "$bin" ingest "$lib" -o "$work/two" -q --jobs 2; t_rerun=$(echo "$(now) - $t0" | bc -l)

rate() { echo "scale=2; $1 / $2" | bc -l; }
printf '%-42s %8s %9s %10s %8s\n' "job" seconds "files/s" "Mpixel/s" "ratio"
printf '%-42s %8.1f %9.1f %10.2f %8s\n' "loop of single-file calls" "$t_loop" "$(rate "$colour" "$t_loop")" "$(rate "$pixels / 1000000" "$t_loop")" "1.00"
printf '%-42s %8.1f %9.1f %10.2f %8.2f\n' "ingest --jobs 1" "$t_one" "$(rate "$colour" "$t_one")" "$(rate "$pixels / 1000000" "$t_one")" "$(rate "$t_loop" "$t_one")"
printf '%-42s %8.1f %9.1f %10.2f %8.2f\n' "ingest --jobs 2" "$t_two" "$(rate "$colour" "$t_two")" "$(rate "$pixels / 1000000" "$t_two")" "$(rate "$t_loop" "$t_two")"
printf '%-42s %8.2f %9.0f\n' "rerun, everything up to date ($files files)" "$t_rerun" "$(rate "$files" "$t_rerun")"
echo "peak RSS of ingest --jobs 2: $(( rss_two / 1024 )) MB (largest file 2048x2048)"
# The outputs are the same files.
diffs=0
for f in $(cd "$work/loop" && find . -name '*.exr'); do
  idiff -q "$work/loop/$f" "$work/two/$f" >/dev/null 2>&1 || diffs=$((diffs + 1))
done
echo "outputs differing from the loop's: $diffs"
