#!/usr/bin/env bash
# Builds the benchmarks in Release and runs them; the JSON goes to out/bench/.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh" bench -DCMAKE_BUILD_TYPE=Release -DRICCI_BUILD_TESTS=OFF \
  -DRICCI_BUILD_BENCHMARKS=ON
mkdir -p "$root/out/bench"
"$root/build/bench/bench/bench_flow" --benchmark_out="$root/out/bench/bench_flow.json" \
  --benchmark_out_format=json "$@"
