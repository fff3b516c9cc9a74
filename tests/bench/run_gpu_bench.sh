#!/usr/bin/env bash
# Direct terms per second of the point sums on the CPU and on the Vulkan device, and the kernel
# summation's time per run on each (16 runs less 1 run, over 15), with the device's ratio to the
# CPU: once with the drivers the loader finds, and once on Mesa's lavapipe (the GPU code on the
# CPU) when installed.
# Usage: tests/bench/run_gpu_bench.sh [build-dir]
set -euo pipefail
build=${1:-build}
out=$(mktemp)
trap 'rm -f "$out"' EXIT
per_run() {  # the kernel frames' time per run, from the JSON of one bench run
  python3 - "$out" <<'PY'
import json, sys
t = {b["name"]: b["real_time"] for b in json.load(open(sys.argv[1]))["benchmarks"] if "error_occurred" not in b}
cpu = None
for dev in ("Cpu", "Gpu"):
    a, b = t.get(f"BM_PsfFrame{dev}/1/iterations:2/real_time"), t.get(f"BM_PsfFrame{dev}/16/iterations:2/real_time")
    if a is None or b is None:
        continue
    run = (b - a) / 15
    cpu = run if dev == "Cpu" else cpu
    ratio = f", {cpu / run:.2f}x the CPU" if dev == "Gpu" and cpu else ""
    print(f"kernel summation, 96x96 frame: {dev}: one run {run:.1f} ms (1 run {a:.0f} ms, 16 runs {b:.0f} ms){ratio}")
PY
}
date -u +"%Y-%m-%d %H:%M UTC, $(nproc) cores"
"$build/tests/bench/bench_gpu_sums" --benchmark_out="$out" --benchmark_out_format=json
per_run
lavapipe=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
if [ -f "$lavapipe" ] && [ "${VK_ICD_FILENAMES:-}" != "$lavapipe" ]; then
  echo "--- lavapipe ---"
  VK_ICD_FILENAMES=$lavapipe "$build/tests/bench/bench_gpu_sums" --benchmark_filter='Gpu|PsfFrameCpu' \
    --benchmark_out="$out" --benchmark_out_format=json
  per_run
fi
