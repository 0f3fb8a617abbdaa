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
  --set scene.points=200000 --set scene.noise=0.002 --set seed=17 --set output.dir="$work/scene"
run=(run configs/demo.yaml --quiet --set input.path="$work/scene/cloud.ply" --set tiling.size=8
     --set threads=1)
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
  # Every tile was run by some rank, once.
  done_count=$(find "$work/ranks$ranks/tiles/runs" -name done | wc -l)
  [ "$done_count" = "$tiles" ] || { echo "FAIL: $done_count of $tiles tiles done"; exit 1; }
done
echo "PASS: $tiles tiles; 2 and 3 ranks wrote the sequential run's bytes"
