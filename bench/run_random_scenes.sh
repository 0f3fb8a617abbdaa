#!/usr/bin/env bash
# slipfit's demo pipeline (configs/demo.yaml, only input and output changed) and CGAL's Efficient
# RANSAC side by side on random labelled scenes (scene_sampling layout: random: 75 shapes of all
# five types, sizes over 20×, random poses, touching and cutting shapes, filleted L-brackets,
# 500–50,000 points each), scored by bench/score_segmentation against the true labels.
#
#   bench/run_random_scenes.sh [build-dir] [seeds ...]     (default seeds: 11 12 13)
#   POINTS=1000000 NOISE=0.002 SHAPES=75 (environment)
#
# CGAL gets PCA normals (k = 18, its own estimator, timed) and the parameters a user who knows the
# scene would give: ε = 3σ (σ = NOISE × the median shape size, ≈ 1.1 units), cluster ε 0.15
# (≈ 3 spacings of the sparsest shapes), min_points 200 (the smallest shape has 500); and a second
# setting with ε = 5σ, cluster ε 0.3. Wall time and peak RSS of each process.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
seeds=${*:-11 12 13}
points=${POINTS:-1000000}
noise=${NOISE:-0.002}
shapes=${SHAPES:-75}
slipfit=$build/pipeline/slipfit
score=$build/bench/score_segmentation
# shellcheck source=bench/ensure_cgal.sh
source "$(dirname "$0")/ensure_cgal.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sigma=$(echo "$noise * 1.1" | bc -l)

printf "| seed | tool | mean IoU | point acc. | type acc. | segments (true %s) | wall s | peak MB |\n" "$shapes"
printf "|---|---|---|---|---|---|---|---|\n"
row() {  # seed tool score-line wall peak
  local s=$3
  get() { echo "$s" | tr ' ' '\n' | grep "^$1=" | cut -d= -f2; }
  printf "| %s | %s | %.3f | %.3f | %.3f | %s | %s | %d |\n" "$1" "$2" "$(get mean_iou)" \
    "$(get point_accuracy)" "$(get type_accuracy)" "$(get segments)" "$4" "$(($5 / 1024))"
}
for seed in $seeds; do
  scene=$work/scene_$seed
  "$slipfit" run configs/sample_scene.yaml --quiet --set scene.layout=random \
    --set scene.shapes="$shapes" --set scene.points="$points" --set scene.noise="$noise" \
    --set seed="$seed" --set output.dir="$scene"
  out=$work/slipfit_$seed
  /usr/bin/time -f "%e %M" -o "$work/time" "$slipfit" run configs/demo.yaml --quiet \
    --set input.path="$scene/cloud.ply" --set output.dir="$out"
  read -r wall peak < "$work/time"
  row "$seed" "slipfit demo" "$("$score" "$scene/cloud.ply" "$out")" "$wall" "$peak"
  if [ -x "$cgal" ]; then
    for factor in 3 5; do
      eps=$(echo "$factor * $sigma" | bc -l)
      cluster=$(echo "0.05 * $factor" | bc -l)
      cout=$work/cgal_${seed}_$factor
      mkdir -p "$cout"
      /usr/bin/time -f "%e %M" -o "$work/time" "$cgal" "$scene/cloud.ply" "$cout" tuned 1 pca \
        "$eps" "$cluster" 200 >/dev/null
      read -r wall peak < "$work/time"
      row "$seed" "CGAL ε = ${factor}σ" "$("$score" "$scene/cloud.ply" "$cout")" "$wall" "$peak"
    done
  fi
done
