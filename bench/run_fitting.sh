#!/usr/bin/env bash
# Medians of 5 repetitions of bench_fitting: estimators from 10^3 to 10^7 points and the
# memory-read baseline at the same sizes.   Usage: bench/run_fitting.sh [build-dir]
set -euo pipefail
build=${1:-build}
"$build/bench/bench_fitting" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true 2>/dev/null |
  grep -E "_median"
