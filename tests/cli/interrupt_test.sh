#!/usr/bin/env bash
# SIGINT and SIGTERM while slipfit writes its outputs: exit 128 + the signal (130, 143), one error
# line, and no file left in output.dir — neither the temporary files nor a partial output.
# Usage: interrupt_test.sh SLIPFIT
set -u
slipfit=$1
scratch=$(mktemp -d /tmp/slipfit_interrupt.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
set -m  # job control: background jobs do not start with SIGINT ignored
status=0
# appears GLOB SECONDS: waits until a file matches GLOB; fails after SECONDS.
appears() {
  for _ in $(seq 1 $(($2 * 100))); do
    compgen -G "$1" >/dev/null && return 0
    sleep 0.01
  done
  return 1
}
for signal in INT TERM; do
  out=$scratch/out
  rm -rf "$out"
  # Writing two million points as ascii PLY takes about a second: time to catch the write.
  printf 'stages: [{type: torus_sampling, points: 2000000}]\noutput: {dir: %s, cloud: big.ply, format: ascii}\n' \
    "$out" >"$scratch/big.yaml"
  "$slipfit" run "$scratch/big.yaml" --quiet 2>"$scratch/err" &
  pid=$!
  if ! appears "$out/.big.tmp.*" 30; then
    echo "FAIL ($signal): no temporary file appeared in $out"
    kill -KILL "$pid" 2>/dev/null
    status=1
    continue
  fi
  kill "-$signal" "$pid"
  wait "$pid"
  code=$?
  expected=$([ "$signal" = INT ] && echo 130 || echo 143)
  left=$(ls -A "$out" 2>/dev/null)
  lines=$(wc -l <"$scratch/err")
  if [ "$code" != "$expected" ] || [ -n "$left" ] || [ "$lines" != 1 ] ||
    ! grep -q '^slipfit: error: .*(SIG'"$signal"')' "$scratch/err"; then
    echo "FAIL ($signal): exit $code (expected $expected), left in $out: '${left}', stderr:"
    cat "$scratch/err"
    status=1
  else
    echo "ok ($signal): exit $code, $out empty, $(cat "$scratch/err")"
  fi
done

# A tiled run interrupted after some tiles have committed their own outputs in the work directory:
# the run's outputs are not written, and the message says so.
configs=$(cd "$(dirname "$0")/../../configs" && pwd)
"$slipfit" run "$configs/sample_scene.yaml" --quiet --set scene.layout=random --set scene.shapes=20 \
  --set scene.points=400000 --set seed=5 --set output.dir="$scratch/scene"
out=$scratch/tiled
"$slipfit" run "$configs/demo.yaml" --quiet --set input.path="$scratch/scene/cloud.ply" \
  --set output.dir="$out" --set tiling.size=3 2>"$scratch/err" &
pid=$!
seen=""
appears "$out/tiles/runs/*/done" 60 && seen=yes
tiles=$(ls "$out/tiles/tiles" 2>/dev/null | wc -l)
done_tiles=$(compgen -G "$out/tiles/runs/*/done" | wc -l)
kill -INT "$pid"
wait "$pid"
code=$?
left=$(ls "$out" 2>/dev/null | grep -v '^tiles$')
if [ -z "$seen" ] || [ "$done_tiles" -ge "$tiles" ] || [ "$code" != 130 ] || [ -n "$left" ] ||
  [ "$(wc -l <"$scratch/err")" != 1 ] ||
  ! grep -q '^slipfit: error: interrupted (SIGINT); no output was written$' "$scratch/err"; then
  echo "FAIL (tiled): $done_tiles of $tiles tiles done, exit $code, left in $out: '${left}', stderr:"
  cat "$scratch/err"
  status=1
else
  echo "ok (tiled): $done_tiles of $tiles tiles done, exit $code, $(cat "$scratch/err")"
fi
exit $status
