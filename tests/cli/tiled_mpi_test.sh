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
echo "PASS: $tiles tiles; 2 and 3 ranks wrote the sequential run's bytes; ranks of another" \
  "config or work directory were refused; a killed rank left no output and the rerun resumed" \
  "after $done_before tiles"
