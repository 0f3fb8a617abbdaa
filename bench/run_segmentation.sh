#!/usr/bin/env bash
# slipfit's segmentation pipeline side by side with CGAL's Efficient RANSAC on labelled scenes
# (scene_sampling: box, cylinder, sphere, cone on a ground plane; 10 % outliers), scored against
# the true labels by bench/score_segmentation.
#
#   bench/run_segmentation.sh [build-dir] [points ...]      (default points: 100000 1000000)
#
# slipfit: the whole demo pipeline (subsample, neighborhoods, normals, local slippage,
# segmentation, fits, all outputs including the PNG), wall time and peak RSS of the process.
# CGAL: Efficient RANSAC with its documented defaults scaled to the scene and with a tuned
# setting, either on slipfit's normals ("given": CGAL's normal estimation not counted) or on
# normals from CGAL::pca_estimate_normals (k = 18, TBB) — the whole pipeline a CGAL user runs;
# the process's wall time and peak RSS, and the detection time alone.
set -euo pipefail
build=${1:-build}
shift || true
sizes=${*:-100000 1000000}
slipfit=$build/pipeline/slipfit
score=$build/bench/score_segmentation
# shellcheck source=bench/ensure_cgal.sh
source "$(dirname "$0")/ensure_cgal.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

printf "| scene | tool | mean IoU | point acc. | type acc. | segments (true 10) | axis err ° mean/max | size err %% mean/max | wall s | detect s | peak MB |\n"
printf "|---|---|---|---|---|---|---|---|---|---|---|\n"
row() {  # scene tool score-line wall peak detect
  local s=$3
  get() { echo "$s" | tr ' ' '\n' | grep "^$1=" | cut -d= -f2; }
  printf "| %s | %s | %.3f | %.3f | %.2f | %s | %.2f / %.2f | %.2f / %.2f | %s | %s | %d |\n" \
    "$1" "$2" "$(get mean_iou)" "$(get point_accuracy)" "$(get type_accuracy)" "$(get segments)" \
    "$(get axis_err_deg_mean)" "$(get axis_err_deg_max)" "$(get size_err_pct_mean)" \
    "$(get size_err_pct_max)" "$4" "$6" "$(($5 / 1024))"
}

for n in $sizes; do
  for noise in 0.005 0.01; do
    name="${n} pts, σ ${noise}, 10 % outliers"
    scene=$work/scene
    "$slipfit" run configs/sample_scene.yaml --quiet --set scene.points="$n" \
      --set scene.noise="$noise" --set scene.outliers=0.1 --set output.dir="$scene"
    out=$work/slipfit
    /usr/bin/time -f "%e %M" -o "$work/time" "$slipfit" run configs/demo.yaml --quiet \
      --set input.path="$scene/cloud.ply" --set output.dir="$out"
    read -r wall peak < "$work/time"
    row "$name" slipfit "$("$score" "$scene/cloud.ply" "$out")" "$wall" "$peak" "–"
    if [ -x "$cgal" ]; then
      for run in "default given" "tuned given" "default pca" "tuned pca"; do
        set -- $run
        cout=$work/cgal_$1_$2
        mkdir -p "$cout"
        input=$out/segments.ply
        [ "$2" = pca ] && input=$scene/cloud.ply
        detect=$(/usr/bin/time -f "%e %M" -o "$work/time" "$cgal" "$input" "$cout" "$1" 1 "$2" |
          sed -n 's/.*, \([0-9.]*\) s detection.*/\1/p')
        read -r wall peak < "$work/time"
        row "$name" "CGAL $1, normals $2" "$("$score" "$scene/cloud.ply" "$cout")" "$wall" "$peak" "$detect"
      done
    fi
  done
done
