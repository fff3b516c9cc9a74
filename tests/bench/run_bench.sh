#!/usr/bin/env bash
# Runs the kernel benchmark and prints the exact kernel's throughput as a ratio against the
# scalar double-precision loop measured in the same run.
# Usage: tests/bench/run_bench.sh [build-dir]
set -euo pipefail
build=${1:-build}
json=$(mktemp)
trap 'rm -f "$json"' EXIT
"$build/tests/bench/bench_kernel" --benchmark_format=console --benchmark_out="$json" --benchmark_out_format=json
python3 - "$json" <<'PY'
import json, sys
runs = {b["name"]: b["terms_per_s"] for b in json.load(open(sys.argv[1]))["benchmarks"]}
base, fast = runs["BM_ScalarDoubleLoop/min_time:1.000/real_time"], runs["BM_ExactKernel/min_time:1.000/real_time"]
print(f"scalar double loop : {base:.3e} terms/s")
print(f"exact kernel       : {fast:.3e} terms/s")
print(f"ratio              : {fast / base:.1f}x (goal >= 25x)")
PY
