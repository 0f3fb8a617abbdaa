#!/usr/bin/env bash
# Tiles bounded by points (tiling.max_points, docs/TILING.md): a dense generated scene (the fixed
# layout, POINTS points on a 4 × 4 ground) run in grid tiles of SIZE under an address-space limit
# (prlimit --as LIMIT), once with tiling.max_points=0 (tiles bounded by area only, as before) and
# once with the default limit. Prints wall seconds, peak RSS, the exit code, the tiling's report
# line and the mean IoU against the truth (score_segmentation).
#
#   bench/run_dense_tiling.sh [build-dir]
#   POINTS=20000000 SIZE=2 LIMIT=1.5G WORK=/tmp/dense_tiling (environment)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
points=${POINTS:-20000000}
size=${SIZE:-2}
limit=${LIMIT:-1.5G}
work=${WORK:-$(mktemp -d)}
mkdir -p "$work"
slipfit=$build/pipeline/slipfit
score=$build/bench/score_segmentation
cloud=$work/scene_$points/cloud.ply
[ -f "$cloud" ] || "$slipfit" run configs/sample_scene.yaml --quiet --set scene.points="$points" \
  --set output.dir="$work/scene_$points" >/dev/null
echo "| tiling.max_points | exit | wall s | peak RSS MB | tiles | fullest core | mean IoU |"
echo "|---|---|---|---|---|---|---|"
for max in 0 default; do
  out=$work/out_$max
  rm -rf "$out"
  args=(run configs/demo.yaml --set input.path="$cloud" --set output.dir="$out"
        --set tiling.size="$size")
  [ "$max" = default ] || args+=(--set tiling.max_points="$max")
  code=0
  /usr/bin/time -f "%e %M" -o "$work/time" prlimit --as="$(numfmt --from=iec "$limit")" \
    "$slipfit" "${args[@]}" >"$work/report" 2>"$work/errors" || code=$?
  read -r wall peak < <(tail -1 "$work/time")
  tiles=$(sed -n 's/^tiling: [0-9]* points.* into \([0-9]*\) tiles.*/\1/p' "$work/report")
  fullest=$(sed -n 's/^  - \[[^,]*, [^,]*, [^,]*, [^,]*, \([0-9]*\),.*/\1/p' \
    "$out/tiles/manifest.yaml" 2>/dev/null | sort -n | tail -1 || true)
  iou=-
  [ "$code" = 0 ] && iou=$("$score" "$cloud" "$out" 2>/dev/null | tr ' ' '\n' |
    sed -n 's/^mean_iou=//p' || true)
  printf "| %s | %s | %s | %d | %s | %s | %s |\n" "$max" "$code" "$wall" $((peak / 1024)) \
    "${tiles:--}" "${fullest:--}" "${iou:--}"
  [ "$code" = 0 ] || sed 's/^/    /' "$work/errors"
done
