#!/usr/bin/env bash
# The demo pipeline (configs/demo.yaml as shipped) on generated scenes of growing size: wall time
# and peak memory of every step (read, each stage, write) in bytes per input point, from the
# run's own report, and the process's wall time and peak RSS from /usr/bin/time. Memory per
# point should stay flat as N grows (linear memory).
#
#   bench/run_large.sh [build-dir] [points ...]      (default points: 1000000 3000000 10000000)
set -euo pipefail
build=${1:-build}
shift || true
sizes=${*:-1000000 3000000 10000000}
slipfit=$build/pipeline/slipfit
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

steps="read sample neighborhoods normals slippage segments write"
printf "| points | step |"
for s in $steps; do printf " %s |" "$s"; done
printf " process |\n|---|---|"
for s in $steps; do printf -- "---|"; done
printf -- "---|\n"
for n in $sizes; do
  "$slipfit" run configs/sample_scene.yaml --quiet --set scene.points="$n" \
    --set output.dir="$work/scene" >/dev/null
  /usr/bin/time -f "%e %M" -o "$work/time" "$slipfit" run configs/demo.yaml \
    --set input.path="$work/scene/cloud.ply" --set output.dir="$work/out" >"$work/report"
  read -r wall peak <"$work/time"
  printf "| %s | seconds |" "$n"
  for s in $steps; do
    printf " %s |" "$(sed -n "s/^  $s: \([0-9.]*\) s,.*/\1/p" "$work/report")"
  done
  printf " %s |\n| | B per point |" "$wall"
  for s in $steps; do
    printf " %s |" "$(sed -n "s/^  $s: .*(\([0-9]*\) B per point)/\1/p" "$work/report")"
  done
  awk -v p="$peak" -v n="$n" 'BEGIN { printf " %.0f (%d MB) |\n", p * 1024 / n, p / 1024 }'
  rm -rf "$work/scene" "$work/out"
done
