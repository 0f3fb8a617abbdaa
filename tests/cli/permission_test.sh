#!/usr/bin/env bash
# Permission denied is named as such: an input the user may not read, an output.dir the user may
# not write. Run as root (as CI does), the checks run as the user nobody through setpriv, since
# root reads and writes anything; the binary is copied next to the files so that nobody reaches
# it wherever the build tree lives. Usage: permission_test.sh SLIPFIT
set -u
scratch=$(mktemp -d /tmp/slipfit_permission.XXXXXX)
trap 'chmod -R u+rwX "$scratch"; rm -rf "$scratch"' EXIT
chmod 755 "$scratch"
mkdir -p "$scratch/locked_out"
slipfit=$1
as_user=()
if [ "$(id -u)" = 0 ]; then
  if ! command -v setpriv >/dev/null; then
    echo "setpriv (util-linux) is missing: cannot drop root's rights"
    exit 1
  fi
  cp "$slipfit" "$scratch/slipfit"
  slipfit=$scratch/slipfit
  as_user=(setpriv --reuid=65534 --regid=65534 --clear-groups)
fi
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n' \
  >"$scratch/secret.ply"
chmod 000 "$scratch/secret.ply"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n' \
  >"$scratch/open.ply"
chmod 644 "$scratch/open.ply"
chmod 555 "$scratch/locked_out"
printf 'input: {path: %s}\nstages: [{type: neighborhood_selection}]\noutput: {dir: %s/out}\n' \
  "$scratch/secret.ply" "$scratch" >"$scratch/unreadable.yaml"
printf 'input: {path: %s}\nstages: [{type: neighborhood_selection}]\noutput: {dir: %s/locked_out}\n' \
  "$scratch/open.ply" "$scratch" >"$scratch/unwritable.yaml"
printf 'input: {path: %s}\nstages: [{type: neighborhood_selection}]\noutput: {dir: %s/locked_out/sub}\n' \
  "$scratch/open.ply" "$scratch" >"$scratch/uncreatable.yaml"
chmod 644 "$scratch"/*.yaml
status=0
check() {  # config, command, expected part of the message
  local err code
  err=$("${as_user[@]}" "$slipfit" "$2" "$scratch/$1" 2>&1 >/dev/null)
  code=$?
  if [ "$code" != 1 ] || [ "$(printf '%s\n' "$err" | wc -l)" != 1 ] || [[ "$err" != *"$3"* ]]; then
    echo "FAIL ($1, $2): exit $code, expected 1 and one line with '$3'; got: $err"
    status=1
  else
    echo "ok ($1, $2): $err"
  fi
}
for command in run validate; do
  check unreadable.yaml $command "secret.ply': cannot be opened: permission denied"
  check unwritable.yaml $command "locked_out': permission denied (cannot create files in it)"
  check uncreatable.yaml $command "locked_out/sub': permission denied (cannot create it in"
done
if [ -n "$(ls -A "$scratch/locked_out")" ] || [ -e "$scratch/out" ]; then
  echo "FAIL: a refused run left files behind"
  status=1
fi
exit $status
