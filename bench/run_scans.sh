#!/usr/bin/env bash
# slipfit's demo pipeline (configs/demo.yaml, only input and output changed) and CGAL's Efficient
# RANSAC side by side on simulated sensor scans with ground truth (configs/sample_scan.yaml: the
# scan_sampling stage), scored by bench/score_segmentation.
#
#   bench/run_scans.sh [build-dir] [seeds ...]        (default seeds: 1 2 3 — the development
#                                                      seeds; the held-out ones are 101 102 103)
#   KINDS="close tabletop far lidar airborne" (environment; the default is all five; two more on
#   request: nolevels — the tabletop camera with depth not on levels, as a time-of-flight camera;
#   millimetres — the same, its depth stored in whole millimetres as OpenNI and RealSense do)
#   SCAN_FORMAT=ply (environment): slipfit reads the PLY of the returns, without the sensor's
#   grid and pose, in place of the organized PCD
#
# Kinds: close — depth camera 0.6–1.0 m from the table; tabletop — 0.8–2.5 m; far — 2–3 m;
# lidar — a terrestrial scanner in the yard; airborne — scan lines from 80 m over the yard.
# CGAL gets PCA normals (k = 18) and the parameters a user who knows the sensor would give: ε ≈
# 3 σ at the scene's typical range (camera 1 cm, 2 cm at range; lidar 2 cm; airborne 6 cm), cluster
# ε ≈ 3 spacings, min_points 100. Prints a Markdown table and the means per tool.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
seeds=${*:-1 2 3}
kinds=${KINDS:-close tabletop far lidar airborne}
slipfit=$build/pipeline/slipfit
score=$build/bench/score_segmentation
# shellcheck source=bench/ensure_cgal.sh
source "$(dirname "$0")/ensure_cgal.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

scan_options() {  # kind -> --set options of configs/sample_scan.yaml
  case $1 in
    close) echo "--set scan.distance_min=0.6 --set scan.distance_max=1.0" ;;
    tabletop) echo "" ;;
    far) echo "--set scan.distance_min=2.0 --set scan.distance_max=3.0" ;;
    lidar) echo "--set scan.sensor=lidar --set scan.scene=yard" ;;
    airborne) echo "--set scan.sensor=airborne --set scan.scene=yard" ;;
    nolevels) echo "--set scan.disparity_step=0" ;;
    millimetres) echo "--set scan.disparity_step=0 --set scan.depth_unit=0.001" ;;
  esac
}
cgal_options() {  # kind -> epsilon cluster_epsilon
  case $1 in
    close | tabletop | nolevels | millimetres) echo "0.01 0.02" ;;
    far) echo "0.02 0.04" ;;
    lidar) echo "0.02 0.1" ;;
    airborne) echo "0.06 0.3" ;;
  esac
}

printf "| kind | seed | tool | mean IoU | type acc. | segments (true) | points | wall s |\n"
printf "|---|---|---|---|---|---|---|---|\n"
: > "$work/all"
row() {  # kind seed tool score-line wall points
  local s=$4
  get() { echo "$s" | tr ' ' '\n' | grep "^$1=" | cut -d= -f2; }
  printf "| %s | %s | %s | %.3f | %.3f | %s (%s) | %s | %s |\n" "$1" "$2" "$3" "$(get mean_iou)" \
    "$(get type_accuracy)" "$(get segments)" "$(get truths)" "$6" "$5"
  echo "$3 $(get mean_iou) $(get type_accuracy) $5" >> "$work/all"
}
for kind in $kinds; do
  for seed in $seeds; do
    scan=$work/scan_${kind}_$seed
    # shellcheck disable=SC2046
    "$slipfit" run configs/sample_scan.yaml --quiet $(scan_options "$kind") --set seed="$seed" \
      --set output.dir="$scan"
    # The same scan as the sensor delivers it (organized PCD, its pose as VIEWPOINT) for slipfit;
    # CGAL and the scorer read the PLY of its returns (slipfit's segments carry its truth fields).
    "$slipfit" run configs/sample_scan.yaml --quiet $(scan_options "$kind") --set seed="$seed" \
      --set output.dir="$scan" --set output.cloud=cloud.pcd
    points=$(head -c 400 "$scan/cloud.ply" | grep -a "^element vertex" | awk '{print $3}')
    out=$work/slipfit_${kind}_$seed
    /usr/bin/time -f "%e" -o "$work/time" "$slipfit" run configs/demo.yaml --quiet \
      --set input.path="$scan/cloud.${SCAN_FORMAT:-pcd}" --set output.dir="$out"
    row "$kind" "$seed" slipfit "$("$score" "$scan/cloud.ply" "$out")" "$(cat "$work/time")" "$points"
    if [ -x "$cgal" ]; then
      read -r eps cluster <<< "$(cgal_options "$kind")"
      cout=$work/cgal_${kind}_$seed
      mkdir -p "$cout"
      /usr/bin/time -f "%e" -o "$work/time" "$cgal" "$scan/cloud.ply" "$cout" tuned 1 pca \
        "$eps" "$cluster" 100 >/dev/null 2>&1
      row "$kind" "$seed" CGAL "$("$score" "$scan/cloud.ply" "$cout")" "$(cat "$work/time")" "$points"
    fi
  done
done
echo
awk '{n[$1]++; iou[$1]+=$2; type[$1]+=$3; t[$1]+=$4; if (!($1 in low) || $2 < low[$1]) low[$1]=$2}
     END {for (k in n) printf "%s: mean IoU %.3f (lowest %.3f), type accuracy %.3f, %.1f s per scan over %d scans\n",
          k, iou[k]/n[k], low[k], type[k]/n[k], t[k]/n[k], n[k]}' "$work/all"
