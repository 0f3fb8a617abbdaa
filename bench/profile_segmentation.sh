#!/usr/bin/env bash
# Where a run's time goes, stage by stage and, inside the segmentation, phase by phase (the
# report's "phases:" line, docs/THEORY.md §6), on the standard clouds: the 1 M-point random scene
# (seed 11, 75 shapes, σ 0.002), PCL's organized tabletop frame and office scan, and the largest
# Fit4CAD part of ../shared. The demo config, input and output only; one thread unless given.
#
#   bench/profile_segmentation.sh [build-dir] [threads]
#
# Prints, per cloud, the stage times and the phases sorted by time with their share of the
# segmentation. Timings are wall times of one run: compare them in one run of the script.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
threads=${2:-1}
slipfit=$build/pipeline/slipfit
out=${PROFILE_OUT:-out/profile}
mkdir -p "$out"
scene=$out/scene_1m/cloud.ply
if [ ! -f "$scene" ]; then
  "$slipfit" run configs/sample_scene.yaml --quiet --set scene.layout=random --set scene.shapes=75 \
    --set scene.points=1000000 --set scene.noise=0.002 --set seed=11 --set output.dir="$out/scene_1m"
fi
clouds=("$scene")
for f in ../shared/data/pcl/table_scene_mug_stereo_textured.pcd ../shared/data/pcl/office1.pcd \
         ../shared/data/fit4cad_train/PC167.ply; do
  [ -f "$f" ] && clouds+=("$f")
done
for cloud in "${clouds[@]}"; do
  name=$(basename "$cloud")
  report=$out/${name%.*}.txt
  "$slipfit" run configs/demo.yaml --set input.path="$cloud" --set threads="$threads" \
    --set output.dir="$out/${name%.*}" >"$report"
  points=$(sed -n 's/^input: .*: \([0-9]*\) points.*/\1/p' "$report")
  echo "== $name: $points points, $threads thread(s)"
  grep -E '^  [a-z_]+: [0-9.]+ s, peak memory' "$report" | sed 's/^  /  stage /'
  sed -n 's/^  phases: //p' "$report" | tr ',' '\n' | sed 's/^ //' |
    awk '{ t[$1] = $2; total += $2 } END {
      n = 0; for (p in t) order[++n] = p
      for (i = 1; i <= n; ++i) for (j = i + 1; j <= n; ++j)
        if (t[order[j]] > t[order[i]]) { x = order[i]; order[i] = order[j]; order[j] = x }
      for (i = 1; i <= n; ++i)
        printf "  phase %-22s %7.2f s  %5.1f %%\n", order[i], t[order[i]], (total > 0 ? 100 * t[order[i]] / total : 0)
    }'
done
