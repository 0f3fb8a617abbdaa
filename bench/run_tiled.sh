#!/usr/bin/env bash
# Tiled runs (docs/TILING.md) at scale, on random scenes of the same kind (13,333 points per
# shape, all five types, σ 0.002): an untiled run of the small scene against tiled runs of the
# small and the large one, and the tile phase shared among MPI ranks. Both analyse at one voxel
# leaf (LEAF), so that "the same kind" means the same analysis density.
#
#   bench/run_tiled.sh [build-dir]
#   SMALL=10000000 LARGE=100000000 SIZE=25 LEAF=0.016 LIMIT=2G WORK=/tmp/tiled_bench (environment)
#
# Prints one line per run: wall seconds, peak RSS, µs per point, the tile phase and the merge
# from the run's report, and mean IoU against the truth; then the MPI speed-up (-np 2 against
# -np 1, one thread a rank) on the small scene's tiles.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
small=${SMALL:-10000000}
large=${LARGE:-100000000}
size=${SIZE:-25}
leaf=${LEAF:-0.016}
limit=${LIMIT:-2G}
work=${WORK:-$(mktemp -d)}
mkdir -p "$work"
slipfit=$build/pipeline/slipfit
score=$build/bench/score_segmentation

scene() {  # points → directory
  local n=$1 dir=$work/scene_$1
  if [ ! -f "$dir/cloud.ply" ]; then
    "$slipfit" run configs/sample_scene.yaml --quiet --set scene.layout=random \
      --set scene.shapes=$((n / 13333)) --set scene.points="$n" --set scene.noise=0.002 \
      --set seed=51 --set output.dir="$dir" >/dev/null
  fi
  echo "$dir/cloud.ply"
}
line() {  # name points report-file time-file out-dir cloud
  local wall peak
  read -r wall peak <"$4"
  printf "| %s | %s | %s | %d | %.2f | %s | %s | %s |\n" "$1" "$2" "$wall" $((peak / 1024)) \
    "$(echo "$wall * 1000000 / $2" | bc -l)" \
    "$(sed -n 's/^tiling: [0-9]* tiles run, [0-9]* already done, \([0-9.]*\) s$/\1/p' "$3")" \
    "$(sed -n 's/^  merge: \([0-9.]*\) s.*/\1/p' "$3")" \
    "$("$score" "$6" "$5" | tr ' ' '\n' | sed -n 's/^mean_iou=//p')"
}
echo "| run | points | wall s | peak MB | µs/point | tiles s | merge s | mean IoU |"
echo "|---|---|---|---|---|---|---|---|"
cloud=$(scene "$small")
run=(run configs/demo.yaml --set input.path="$cloud" --set sample.leaf="$leaf")
/usr/bin/time -f "%e %M" -o "$work/time" "$slipfit" "${run[@]}" --set output.dir="$work/untiled" \
  >"$work/report"
line "untiled" "$small" "$work/report" "$work/time" "$work/untiled" "$cloud"
rm -rf "$work/tiled_small"
/usr/bin/time -f "%e %M" -o "$work/time" "$slipfit" "${run[@]}" \
  --set output.dir="$work/tiled_small" --set tiling.size="$size" >"$work/report"
line "tiled $size" "$small" "$work/report" "$work/time" "$work/tiled_small" "$cloud"

# MPI: the same tiles, one thread a rank; the tile phase of 1 and 2 ranks.
if command -v mpirun >/dev/null; then
  as_root=()
  [ "$(id -u)" = 0 ] && as_root=(--allow-run-as-root)
  for ranks in 1 2; do
    rm -rf "$work/tiled_small/tiles/runs"
    mpirun "${as_root[@]}" -np "$ranks" "$slipfit" "${run[@]}" --set threads=1 \
      --set output.dir="$work/tiled_small" --set tiling.size="$size" >"$work/mpi_$ranks"
    echo "mpirun -np $ranks: $(grep 'tiles run' "$work/mpi_$ranks")"
  done
fi

cloud=$(scene "$large")
rm -rf "$work/tiled_large"
/usr/bin/time -f "%e %M" -o "$work/time" prlimit --as=$(numfmt --from=iec "$limit") \
  "$slipfit" "${run[@]}" --set input.path="$cloud" --set output.dir="$work/tiled_large" \
  --set tiling.size="$size" >"$work/report"
line "tiled $size, --as $limit" "$large" "$work/report" "$work/time" "$work/tiled_large" "$cloud"
