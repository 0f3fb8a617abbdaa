#!/usr/bin/env bash
# Medians of 5 repetitions for bench_torus, and the peak memory of the largest sample and mesh
# cases, each in its own process.   Usage: bench/run_torus.sh [build-dir]
set -euo pipefail
build=${1:-build}
exe="$build/bench/bench_torus"
"$exe" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true 2>/dev/null | grep -E "_median"
for case in 'BM_TorusSampleArea/1000000' 'BM_TorusMesh/1000'; do
  /usr/bin/time -f "$case peak_rss_kb=%M" "$exe" --benchmark_filter="^${case}\$" 2>&1 >/dev/null | grep peak_rss
done
