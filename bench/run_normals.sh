#!/usr/bin/env bash
# Medians of 5 repetitions and peak memory (each case in its own process) for bench_normals.
# Usage: bench/run_normals.sh [build-dir]
set -euo pipefail
build=${1:-build}
exe="$build/bench/bench_normals"
for case in BM_PclNormalEstimationOMP BM_SlipfitNormalEstimation BM_SlipfitNormalStage \
            'BM_SlipfitNeighborhoodsThenNormals/0' 'BM_SlipfitNeighborhoodsThenNormals/1'; do
  /usr/bin/time -f "$case peak_rss_kb=%M" "$exe" --benchmark_filter="^${case}(/real_time)?\$" \
    --benchmark_repetitions=5 --benchmark_report_aggregates_only=true 2>&1 |
    grep -E "_median|peak_rss"
done
