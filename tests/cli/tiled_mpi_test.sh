#!/usr/bin/env bash
# A tiled run shared among MPI ranks writes the bytes of the same tiled run in one process:
# mpirun -np 2, and --oversubscribe -np 3 (more ranks than cores), against the sequential run.
#   tiled_mpi_test.sh SLIPFIT MPIEXEC
set -euo pipefail
slipfit=$1
mpiexec=$2
cd "$(dirname "$0")/../.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$slipfit" run configs/sample_scene.yaml --quiet --set scene.layout=random --set scene.shapes=30 \
  --set scene.points=100000 --set scene.noise=0.002 --set seed=17 --set output.dir="$work/scene"
loud=(run configs/demo.yaml --set input.path="$work/scene/cloud.ply" --set tiling.size=8
      --set threads=1)
run=("${loud[@]}" --quiet)
"$slipfit" "${run[@]}" --set output.dir="$work/sequential"
tiles=$(grep -c '^  - \[' "$work/sequential/tiles/manifest.yaml")
[ "$tiles" -ge 9 ] || { echo "FAIL: only $tiles tiles"; exit 1; }
# Root may run mpirun in CI containers only when it says so.
as_root=()
[ "$(id -u)" = 0 ] && as_root=(--allow-run-as-root)
for ranks in 2 3; do
  "$mpiexec" "${as_root[@]}" --oversubscribe -np "$ranks" "$slipfit" "${run[@]}" \
    --set output.dir="$work/ranks$ranks"
  for f in segments.ply primitives.yaml; do
    cmp "$work/sequential/$f" "$work/ranks$ranks/$f" ||
      { echo "FAIL: $f of $ranks ranks differs from the sequential run"; exit 1; }
  done
  # The ranks tile together, each its share of the input's rows: the tiles are the sequential
  # run's bytes.
  for t in "$work/sequential/tiles/tiles/"*.ply; do
    cmp "$t" "$work/ranks$ranks/tiles/tiles/$(basename "$t")" ||
      { echo "FAIL: $(basename "$t") of $ranks ranks differs from the sequential run's"; exit 1; }
  done
  # Every tile was run by some rank, once.
  done_count=$(find "$work/ranks$ranks/tiles/runs" -name done | wc -l)
  [ "$done_count" = "$tiles" ] || { echo "FAIL: $done_count of $tiles tiles done"; exit 1; }
done
# Issue 40: ranks that do not share the run. A rank started with another config (MPMD), and a
# rank whose work directory is not the first rank's: every rank refuses before any tile, no
# output is written, and the message says why.
mpmd() {  # mpmd NAME ARGS-OF-RANK-1...
  local name=$1
  shift
  if "$mpiexec" "${as_root[@]}" --oversubscribe -np 1 "$slipfit" "${run[@]}" \
    --set output.dir="$work/$name" --set tiling.workdir="$work/$name.work" : \
    -np 1 "$slipfit" "${run[@]}" --set output.dir="$work/$name" "$@" \
    >"$work/$name.out" 2>"$work/$name.err"; then
    echo "FAIL: $name: mpirun succeeded"; exit 1
  fi
  [ ! -e "$work/$name/segments.ply" ] || { echo "FAIL: $name wrote segments.ply"; exit 1; }
  [ -z "$(find "$work/$name.work" -name done 2>/dev/null)" ] ||
    { echo "FAIL: $name ran tiles"; exit 1; }
}
mpmd other_config --set tiling.workdir="$work/other_config.work" --set segments.max_angle=25
grep -q "this rank's config differs from the first rank's" "$work/other_config.err" ||
  { echo "FAIL: other config not refused"; cat "$work/other_config.err"; exit 1; }
mpmd other_workdir --set tiling.workdir="$work/elsewhere"
grep -q "is not the one the first rank claimed" "$work/other_workdir.err" ||
  { echo "FAIL: other workdir not refused"; cat "$work/other_workdir.err"; exit 1; }
# A rank that dies (kill -9 once two tiles are done): mpirun ends the job with a non-zero exit,
# rank 0 says no output was written and none is; a rerun in one process resumes from the
# finished tiles and writes the sequential run's bytes.
killed=$work/killed
"$mpiexec" "${as_root[@]}" --oversubscribe -np 2 "$slipfit" "${run[@]}" \
  --set output.dir="$killed" >"$work/killed.out" 2>"$work/killed.err" &
launcher=$!
for _ in $(seq 1 600); do
  [ "$(find "$killed/tiles/runs" -name done 2>/dev/null | wc -l)" -ge 2 ] && break
  sleep 0.1
done
victim=""
for pid in $(pgrep -f -- "--set output.dir=$killed\$"); do  # rank 1, by its environment
  tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=1" && victim=$pid
done
[ -n "$victim" ] || { echo "FAIL: no rank 1 to kill"; exit 1; }
kill -9 "$victim"
if wait "$launcher"; then echo "FAIL: mpirun succeeded after a rank was killed"; exit 1; fi
grep -q "no output was written" "$work/killed.err" ||
  { echo "FAIL: rank 0 did not say that no output was written"; cat "$work/killed.err"; exit 1; }
for f in segments.ply primitives.yaml segments.png; do
  [ ! -e "$killed/$f" ] || { echo "FAIL: $f written by the killed run"; exit 1; }
done
"$slipfit" "${loud[@]}" --set output.dir="$killed" >"$work/resumed.out"
done_before=$(sed -n 's/^tiling: [0-9]* tiles run, \([0-9]*\) already done.*/\1/p' "$work/resumed.out")
[ "${done_before:-0}" -ge 2 ] || { echo "FAIL: the rerun did not resume"; cat "$work/resumed.out"; exit 1; }
for f in segments.ply primitives.yaml; do
  cmp "$work/sequential/$f" "$killed/$f" || { echo "FAIL: resumed $f differs"; exit 1; }
done
# The ranks share the reading of the input: tiling.size: auto's read, and a failure in one
# rank's rows. On 3 ranks the auto size and its outputs are the sequential run's; a non-finite
# coordinate in the last rank's rows under input.nan: error is the sequential run's one line on
# every rank's behalf, and nothing is written.
"$slipfit" "${run[@]}" --set output.dir="$work/auto1" --set tiling.size=auto \
  --set tiling.max_points=20000
"$mpiexec" "${as_root[@]}" --oversubscribe -np 3 "$slipfit" "${run[@]}" \
  --set output.dir="$work/auto3" --set tiling.size=auto --set tiling.max_points=20000
for f in segments.ply primitives.yaml; do
  cmp "$work/auto1/$f" "$work/auto3/$f" ||
    { echo "FAIL: $f of tiling.size=auto on 3 ranks differs from the sequential run"; exit 1; }
done
cmp "$work/auto1/tiles/manifest.yaml" "$work/auto3/tiles/manifest.yaml" ||
  { echo "FAIL: the auto tiling's manifest differs on 3 ranks"; exit 1; }
nan=$work/nan.ply
{
  printf 'ply\nformat ascii 1.0\nelement vertex 3000\nproperty float x\nproperty float y\n'
  printf 'property float z\nend_header\n'
  for i in $(seq 0 2999); do
    if [ "$i" = 2500 ]; then echo "nan 1 0"; else echo "$((i % 60)).5 $((i / 60)).5 0"; fi
  done
} >"$nan"
nan_run=(run configs/demo.yaml --quiet --set input.path="$nan" --set tiling.size=20
         --set input.nan=error --set threads=1)
if "$slipfit" "${nan_run[@]}" --set output.dir="$work/nan1" 2>"$work/nan1.err"; then
  echo "FAIL: a non-finite coordinate was accepted"; exit 1
fi
if "$mpiexec" "${as_root[@]}" --oversubscribe -np 3 "$slipfit" "${nan_run[@]}" \
  --set output.dir="$work/nan3" >/dev/null 2>"$work/nan3.err"; then
  echo "FAIL: a non-finite coordinate was accepted on 3 ranks"; exit 1
fi
grep -q "point 2500 has a non-finite coordinate" "$work/nan1.err" ||
  { echo "FAIL: the sequential run did not name row 2500"; cat "$work/nan1.err"; exit 1; }
grep -q "^slipfit: error: input '$nan': point 2500 has a non-finite coordinate.* (rank 2)$" \
  "$work/nan3.err" || { echo "FAIL: 3 ranks did not name row 2500"; cat "$work/nan3.err"; exit 1; }
[ ! -e "$work/nan3/segments.ply" ] || { echo "FAIL: segments.ply written"; exit 1; }
echo "PASS: $tiles tiles; 2 and 3 ranks wrote the sequential run's bytes and tiles (tiling.size" \
  "auto too); a non-finite point in rank 2's rows was refused on every rank; ranks of another" \
  "config or work directory were refused; a killed rank left no output and the rerun resumed" \
  "after $done_before tiles"
