#!/usr/bin/env bash
# Medians of 5 repetitions of bench_slippage.   Usage: bench/run_slippage.sh [build-dir]
set -euo pipefail
build=${1:-build}
"$build/bench/bench_slippage" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true 2>/dev/null |
  grep -E "_median"
