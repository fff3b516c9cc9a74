#!/usr/bin/env bash
# Direct terms per second of the exact sums on the CPU and on the Vulkan device: once with the
# drivers the loader finds, and once on Mesa's lavapipe (the GPU code on the CPU) when installed.
# Usage: tests/bench/run_gpu_bench.sh [build-dir]
set -euo pipefail
build=${1:-build}
date -u +"%Y-%m-%d %H:%M UTC, $(nproc) cores"
"$build/tests/bench/bench_gpu_sums"
lavapipe=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
if [ -f "$lavapipe" ] && [ "${VK_ICD_FILENAMES:-}" != "$lavapipe" ]; then
  echo "--- lavapipe ---"
  VK_ICD_FILENAMES=$lavapipe "$build/tests/bench/bench_gpu_sums" --benchmark_filter=Gpu
fi
