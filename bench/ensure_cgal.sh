#!/usr/bin/env bash
# Makes the CGAL peer of the segmentation benches (build/bench/cgal_ransac) available on a fresh
# Debian 12 machine: installs libcgal-dev when it is missing (as root; otherwise says how), then
# configures and builds the peer. Sourced by bench/run_segmentation.sh and run_random_scenes.sh
# with $build set; leaves $cgal executable or prints one line saying why not.
cgal=$build/bench/cgal_ransac
if [ ! -x "$cgal" ]; then
  if ! dpkg-query -W -f='${Status}' libcgal-dev 2>/dev/null | grep -q "install ok installed"; then
    if [ "$(id -u)" -eq 0 ]; then
      echo "bench: installing libcgal-dev (the CGAL peer)" >&2
      DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
          libcgal-dev >/dev/null || true
    fi
  fi
  if dpkg-query -W -f='${Status}' libcgal-dev 2>/dev/null | grep -q "install ok installed"; then
    cmake -S "$(dirname "$0")/.." -B "$build" >/dev/null &&
      cmake --build "$build" -j2 --target cgal_ransac >/dev/null || true
  fi
  [ -x "$cgal" ] ||
    echo "CGAL peer missing: apt-get install libcgal-dev (as root), then re-run this script" >&2
fi
