#!/usr/bin/env bash
# Farm scale-out for real: a private single-node Slurm (munged, slurmctld, slurmd on 127.0.0.1,
# from a generated config in a temporary folder) runs `spectralize ingest` as a 3-task job array
# over a generated library; a dependent job merges the manifests; every output and the merged
# manifest are checked; the daemons are stopped. Exit 77 (skipped, said loudly) where the
# daemons cannot start.
# Usage: slurm_ingest_test.sh SPECTRALIZE_BINARY SOURCE_DIR
set -euo pipefail
bin="$(readlink -f "$1")"
src="$(readlink -f "$2")"
work="$(mktemp -d /tmp/spectralize-farm.XXXXXX)"
cluster="$work/cluster"
cleanup() {
  bash "$src/tests/farm/slurm_cluster.sh" stop "$cluster" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT

# A small library: colour textures, data maps, environment maps, in folders.
mkdir -p "$work/lib/walls" "$work/lib/props/crate" "$work/lib/sky"
t="$src/testimages"
for n in 1 2 3; do
  cp "$t/colorchecker_srgb8.png" "$work/lib/walls/wall${n}_basecolor.png"
  cp "$t/grey_ramp8.png" "$work/lib/walls/wall${n}_roughness.png"
done
cp "$t/colorchecker_srgb16.png" "$work/lib/props/crate/crate_albedo.png"
cp "$t/grey_ramp8.png" "$work/lib/props/crate/crate_normal.png"
cp "$t/colorchecker_srgb8_rgba.png" "$work/lib/props/crate/label_diffuse.png"
cp "$t/hdri_forest_256x128.exr" "$work/lib/sky/forest_hdri.exr"
cp "$t/hdri_sunset_256x128.hdr" "$work/lib/sky/sunset_env.hdr"
cp "$t/hdri_sunset_256x128.exr" "$work/lib/sky/sunset_sky.exr"
files=$(find "$work/lib" -type f | wc -l)

status=0
bash "$src/tests/farm/slurm_cluster.sh" start "$cluster" || status=$?
if [ "$status" -eq 77 ]; then
  echo "SKIPPED: the Slurm farm test did not run: Slurm or munge cannot start here (see above)"
  exit 77
elif [ "$status" -ne 0 ]; then
  echo "FAILED: the private Slurm cluster did not start (exit $status)"
  exit 1
fi
# shellcheck disable=SC1091
. "$cluster/env.sh"

job=$(sbatch --parsable --array=0-2 --chdir="$work" --partition="$TEST_SLURM_PARTITION" \
  --output="$work/task_%a.log" --export="ALL,SPECTRALIZE=$bin" \
  "$src/farm/spectralize-ingest.sbatch" "$work/lib" "$work/out" --cache "$work/cache")
merge=$(sbatch --parsable --dependency="afterany:$job" --chdir="$work" \
  --partition="$TEST_SLURM_PARTITION" --output="$work/merge.log" \
  --wrap "'$bin' ingest --merge -o '$work/out'")

# Wait for both jobs by polling squeue (sbatch --wait polls every 32 s); at most 180 s.
deadline=$(( $(date +%s) + 180 ))
while :; do
  states=$(squeue -h -j "$job,$merge" -t all -o %T 2>/dev/null || true)
  if [ -n "$states" ] && ! echo "$states" | grep -qvE \
      '^(COMPLETED|FAILED|CANCELLED|TIMEOUT|NODE_FAIL|OUT_OF_MEMORY|PREEMPTED|BOOT_FAIL|DEADLINE)'; then
    break
  fi
  if [ "$(date +%s)" -gt "$deadline" ]; then
    echo "FAILED: the array job did not finish in 180 s; states:"; echo "$states"
    cat "$work"/task_*.log 2>/dev/null || true
    exit 1
  fi
  sleep 0.5
done
echo "job states: $(echo "$states" | sort | uniq -c | tr '\n' ' ')"
cat "$work"/task_*.log "$work/merge.log"

fail() { echo "FAILED: $*"; exit 1; }
for s in 0 1 2; do
  [ -s "$work/out/spectralize-ingest.part-$s-of-3.jsonl" ] || fail "no manifest part of shard $s"
done
manifest="$work/out/spectralize-ingest.jsonl"
[ -s "$manifest" ] || fail "no merged manifest"
records=$(grep -c '"input"' "$manifest")
[ "$records" -eq "$files" ] || fail "$records records for $files files"
converted=$(grep -c '"status":"converted"' "$manifest")
skipped=$(grep -c '"status":"skipped_data"' "$manifest")
[ "$converted" -eq 8 ] || fail "$converted converted (expected 8)"
[ "$skipped" -eq 4 ] || fail "$skipped data maps skipped (expected 4)"
grep -q '"failed":0' "$manifest" || fail "failures in the manifest"
for f in walls/wall1_basecolor walls/wall3_basecolor props/crate/crate_albedo \
         props/crate/label_diffuse sky/forest_hdri sky/sunset_env sky/sunset_sky; do
  [ -s "$work/out/$f.exr" ] || fail "missing output $f.exr"
done
grep -q '"mode":"emission","mode_reason":"name word' "$manifest" || fail "no emission by a name word"
[ -z "$(find "$work/out" -name '.*.tmp')" ] || fail "temporary files left"
echo "RAN: the Slurm farm test: 3 array tasks on a private Slurm at 127.0.0.1 converted $converted files, skipped $skipped data maps, merged manifest $records records"
