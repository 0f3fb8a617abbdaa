#!/usr/bin/env bash
# slipfit's demo pipeline (configs/demo.yaml, only input and output changed) on every cloud of the
# Fit4CAD training set in ../shared/data/fit4cad_train (GPL-3 data, read in place, never copied),
# scored by ../shared/tools/fit4cad_score.py (the benchmark's own Sørensen–Dice, Hungarian mIoU,
# type accuracy).
#
#   bench/run_fit4cad.sh [build-dir] [clouds] [config]   clouds: the scorer's list, e.g. 1-40,77
#
# FIT4CAD_SPLIT=development or held_out runs one half of the set (fixed by the MD5 of each cloud's
# name: 91 and 97 clouds); develop on the first, look at the second only to report (issue 36).
# Prints the scorer's summary and the ten clouds that lose most (1 - Dice); the scorer's table goes
# to $FIT4CAD_OUT/scores.txt and every cloud, sorted by the loss, to $FIT4CAD_OUT/losses.txt
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
case ${FIT4CAD_SPLIT:-all} in
  all) ;;
  development | held_out)
    # The half a cloud belongs to: the parity of the first byte of its name's MD5 (even:
    # development), fixed whatever the build or the order of the files.
    mapfile -t list < <(python3 -c '
import hashlib, sys
want = 0 if sys.argv[1] == "development" else 1
print("\n".join(n for n in sys.argv[2:] if hashlib.md5(n.encode()).digest()[0] % 2 == want))' \
      "$FIT4CAD_SPLIT" "${list[@]}")
    clouds=${clouds:-1-100000}
    ;;
  *)
    echo "run_fit4cad: FIT4CAD_SPLIT is all, development or held_out, not '$FIT4CAD_SPLIT'" >&2
    exit 1
    ;;
esac
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
# The clouds run, as the scorer's list.
scored=$(printf '%s\n' "${list[@]}" | sed 's/^PC//' | paste -sd, -)
[ "${FIT4CAD_SPLIT:-all}" != all ] || [ -n "$clouds" ] && args=(--clouds "$scored")
${PYTHON:-/usr/bin/python3} "$score" "$data" "$out" "${args[@]}" --json "$out/scores.json" >"$out/scores.txt"
tail -3 "$out/scores.txt"
# Every cloud by its loss (1 - Dice), largest first: where the next change should look.
/usr/bin/python3 - "$out/scores.json" >"$out/losses.txt" <<'PY'
import json, sys
clouds = json.load(open(sys.argv[1]))["per_cloud"].values()
print(f"{'cloud':<7} {'points':>7} {'true':>5} {'found':>5} {'dice':>6} {'prec':>6} {'rec':>6} {'mIoU':>6}")
for c in sorted(clouds, key=lambda c: c["paper"]["dice"]):
    p = c["paper"]
    print(f"{c['cloud']:<7} {c['n_points']:>7} {c['n_gt']:>5} {c['n_pred']:>5} {p['dice']:>6.3f} "
          f"{p['precision']:>6.3f} {p['recall']:>6.3f} {c['miou']:>6.3f}")
PY
echo "the ten clouds that lose most (all in $out/losses.txt):"
head -11 "$out/losses.txt"
