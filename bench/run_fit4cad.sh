#!/usr/bin/env bash
# slipfit's demo pipeline (configs/demo.yaml, only input and output changed) on every cloud of the
# Fit4CAD training set in ../shared/data/fit4cad_train (GPL-3 data, read in place, never copied),
# scored by ../shared/tools/fit4cad_score.py (the benchmark's own Sørensen–Dice, Hungarian mIoU,
# type accuracy).
#
#   bench/run_fit4cad.sh [build-dir] [clouds] [config]   clouds: the scorer's list, e.g. 1-40,77
#
# Prints the scorer's summary; the per-cloud table goes to $FIT4CAD_OUT/scores.txt
# (default out/fit4cad).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
clouds=${2:-}
config=${3:-configs/demo.yaml}
data=${FIT4CAD_DIR:-../shared/data/fit4cad_train}
score=../shared/tools/fit4cad_score.py
out=${FIT4CAD_OUT:-out/fit4cad}
if [ ! -d "$data" ]; then
  echo "run_fit4cad: $data is absent (the Fit4CAD training set); nothing to run" >&2
  exit 0
fi
if ! ${PYTHON:-/usr/bin/python3} -c 'import numpy, scipy' 2>/dev/null; then
  echo "run_fit4cad: the scorer needs numpy and scipy: apt-get install python3-numpy python3-scipy" >&2
  exit 1
fi
mkdir -p "$out"
list=()
for gt in "$data"/PC*.gt.json; do
  name=$(basename "$gt" .gt.json)
  list+=("$name")
done
if [ -n "$clouds" ]; then
  mapfile -t list < <(python3 -c '
import sys
spec, names = sys.argv[1], sys.argv[2:]
want = set()
for part in filter(None, spec.split(",")):
    a, _, b = part.partition("-")
    want.update(range(int(a), int(b or a) + 1))
print("\n".join(n for n in names if int(n[2:]) in want))' "$clouds" "${list[@]}")
fi
start=$(date +%s.%N)
run_one() {
  "$build/pipeline/slipfit" run "$config" --quiet --set threads=1 --set input.path="$data/$1.ply" \
    --set output.dir="$out/$1" --set 'segments.render=""' 2>"$out/$1.err" ||
    echo "$1 failed: $(cat "$out/$1.err")"
}
export -f run_one
export build config data out
printf '%s\n' "${list[@]}" | xargs -P "${JOBS:-2}" -I{} bash -c 'run_one {}'
end=$(date +%s.%N)
echo "clouds: ${#list[@]}, wall $(echo "$end - $start" | bc) s with ${JOBS:-2} jobs"
args=()
[ -n "$clouds" ] && args=(--clouds "$clouds")
${PYTHON:-/usr/bin/python3} "$score" "$data" "$out" "${args[@]}" --json "$out/scores.json" >"$out/scores.txt"
tail -3 "$out/scores.txt"
