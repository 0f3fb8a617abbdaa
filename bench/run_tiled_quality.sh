#!/usr/bin/env bash
# Tiled against untiled runs of the demo config on random 1 M-point scenes (75 shapes of all five
# types, σ 0.002; tiles of SIZE units, about 20 a scene): mean IoU, point and type accuracy of
# each, and the difference, scored by bench/score_segmentation against the true labels (which
# both outputs carry, so the tiled run's point order does not matter).
#
#   bench/run_tiled_quality.sh [build-dir] [seeds ...]     (default: 11 12 13 21 31 32 33 34 35 36)
#   SIZE=15 (environment)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
seeds=${*:-11 12 13 21 31 32 33 34 35 36}
size=${SIZE:-15}
slipfit=$build/pipeline/slipfit
score=$build/bench/score_segmentation
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
get() { echo "$2" | tr ' ' '\n' | sed -n "s/^$1=//p"; }
echo "| seed | tiles | untiled IoU | tiled IoU | difference | untiled s | tiled s |"
echo "|---|---|---|---|---|---|---|"
for seed in $seeds; do
  "$slipfit" run configs/sample_scene.yaml --quiet --set scene.layout=random --set scene.shapes=75 \
    --set scene.points=1000000 --set scene.noise=0.002 --set seed="$seed" \
    --set output.dir="$work/scene"
  cloud=$work/scene/cloud.ply
  /usr/bin/time -f "%e" -o "$work/t_untiled" "$slipfit" run configs/demo.yaml --quiet \
    --set input.path="$cloud" --set output.dir="$work/untiled"
  /usr/bin/time -f "%e" -o "$work/t_tiled" "$slipfit" run configs/demo.yaml --quiet \
    --set input.path="$cloud" --set output.dir="$work/tiled" --set tiling.size="$size"
  a=$(get mean_iou "$("$score" "$cloud" "$work/untiled")")
  b=$(get mean_iou "$("$score" "$cloud" "$work/tiled")")
  printf "| %s | %s | %s | %s | %+.4f | %s | %s |\n" "$seed" \
    "$(grep -c '^  - \[' "$work/tiled/tiles/manifest.yaml")" "$a" "$b" "$(echo "$b - $a" | bc -l)" \
    "$(cat "$work/t_untiled")" "$(cat "$work/t_tiled")"
  rm -rf "$work/untiled" "$work/tiled"
done
