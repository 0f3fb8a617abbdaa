#!/usr/bin/env bash
# Every PLY a shipped config writes, slipfit reads back (issue 15): the config runs into a
# scratch output.dir, then each PLY it wrote is read as an input and written again through a
# stage that changes nothing (a crop keeping every point): the vertex properties must come back. Usage: roundtrip_test.sh SLIPFIT CONFIG (run from the source tree, as the README).
set -u
slipfit=$1
config=$2
scratch=$(mktemp -d /tmp/slipfit_roundtrip.XXXXXX)
trap 'rm -rf "$scratch"' EXIT
if ! "$slipfit" run "$config" --quiet --set "output.dir=$scratch/out" 2>"$scratch/err"; then
  echo "FAIL: $config did not run: $(cat "$scratch/err")"
  exit 1
fi
vertexProperties() {  # the names of the vertex element's properties, sorted
  sed -n '/^end_header/q;p' "$1" | awk '/^element/ {v = ($2 == "vertex")} v && /^property/ {print $NF}' |
    sort | tr '\n' ' '
}
status=0
count=0
for ply in "$scratch"/out/*.ply; do
  [ -e "$ply" ] || continue
  count=$((count + 1))
  printf 'input: {path: %s}\nstages: [{type: crop, field: x, min: -1e38, max: 1e38}]\noutput: {dir: %s/back, cloud: back.ply}\n' \
    "$ply" "$scratch" >"$scratch/back.yaml"
  if ! out=$("$slipfit" run "$scratch/back.yaml" 2>&1); then
    echo "FAIL: $(basename "$ply") written by $config does not read back: $out"
    status=1
    continue
  fi
  # The vertex properties it was written with are all there again (a mesh's faces are not read).
  written=$(vertexProperties "$ply")
  again=$(vertexProperties "$scratch/back/back.ply")
  if [ "$written" != "$again" ]; then
    echo "FAIL: $(basename "$ply"): written with [$written], read back and written as [$again]"
    status=1
  else
    echo "ok: $(basename "$ply") ($(echo "$out" | head -1))"
  fi
  rm -rf "$scratch/back"
done
echo "$count PLY files from $config"
exit $status
