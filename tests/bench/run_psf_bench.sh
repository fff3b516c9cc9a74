#!/usr/bin/env bash
# Times one fast-path PSF kernel per pinhole (0.02 to 5 mm, a 512-wide 40deg frame at f = 50 mm) and prints
# each as a ratio against the optimum 0.315 mm measured in the same run (goal: each <= 3x).
# The kernel is built on one thread: CPU time is its cost, steady on a shared machine.
# Usage: tests/bench/run_psf_bench.sh [build-dir]
set -euo pipefail
build=${1:-build}
json=$(mktemp)
trap 'rm -f "$json"' EXIT
"$build/tests/bench/bench_fresnel_psf" --benchmark_format=console --benchmark_out="$json" --benchmark_out_format=json
python3 - "$json" <<'PY'
import json, sys
runs = json.load(open(sys.argv[1]))["benchmarks"]
for family in ("BM_FieldPsfKernel", "BM_FieldPsfKernelCap32"):
    times = {int(b["name"].split("/")[1]): (b["cpu_time"], int(b["radius"])) for b in runs
             if b["name"].split("/")[0] == family}
    base = times[315][0]
    print(f"{family} (ratio to 0.315 mm, goal <= 3x):")
    for um, (t, radius) in sorted(times.items()):
        print(f"  {um / 1000:5.3f} mm  radius {radius:3d}  {t:8.2f} ms CPU  {t / base:5.2f}x")
PY
