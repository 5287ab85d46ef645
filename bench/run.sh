#!/usr/bin/env bash
# Builds the benchmarks in Release and runs them; the JSON goes to out/bench/.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$root/scripts/setup.sh"
bash "$root/scripts/build.sh" bench -DCMAKE_BUILD_TYPE=Release -DRICCI_BUILD_TESTS=OFF \
  -DRICCI_BUILD_BENCHMARKS=ON
mkdir -p "$root/out/bench"
for program in bench_flow bench_uniformize bench_command bench_atlas; do
  "$root/build/bench/bench/$program" --benchmark_out="$root/out/bench/$program.json" \
    --benchmark_out_format=json "$@"
done
