#!/usr/bin/env bash
# The chooser's estimates against the time each evaluator takes (bench_summation_choice.cpp):
# per case and summation, the estimate, the measured time, their ratio (measured / estimated;
# goal: within 2 either way) and the chooser's reason. About 5 minutes on 2 cores.
# Usage: tests/bench/run_choice_bench.sh [build-dir]
set -euo pipefail
build=${1:-build}
out=$(mktemp)
trap 'rm -f "$out"' EXIT
OMP_WAIT_POLICY=passive "$build/tests/bench/bench_summation_choice" --benchmark_out="$out" \
  --benchmark_out_format=json >/dev/null
python3 - "$out" <<'PY'
import json, sys
runs = json.load(open(sys.argv[1]))["benchmarks"]
print(f"term rate measured at the start: {runs[0].get('term_rate', 0):.3g} terms/s")
words = {"0": "auto", "1": "direct", "2": "nufft", "3": "kernel"}
print(f"{'case':28} {'summation':9} {'estimated s':>11} {'measured s':>10} {'ratio':>6}  reason")
for b in runs:
    name, arg = b["name"].split("/")[0][3:], b["name"].split("/")[1]
    if "error_occurred" in b:
        print(f"{name:28} {words[arg]:9} error: {b.get('error_message', '')}")
        continue
    e, m = b["estimated_s"], b["measured_s"]
    flag = "" if e > 0 and 0.5 <= m / e <= 2 else "  (off by more than 2x)"
    print(f"{name:28} {words[arg]:9} {e:11.2f} {m:10.2f} {m / e if e else 0:6.2f}  {b.get('label', '')}{flag}")
PY
