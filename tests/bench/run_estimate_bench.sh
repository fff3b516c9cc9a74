#!/usr/bin/env bash
# What the command says a job will take against what it takes, as a user sees both: for each job,
# `wavecam estimate` (the time printed before work, the same line apply prints) and the wall time
# of `wavecam apply` on the same frame, and their ratio (measured / estimated; goal: within 2
# either way). --busy runs every job beside two CPU-bound loops (the estimate's rate is measured
# as it starts, so it should follow the machine); the GPU rows on lavapipe where it is installed.
# About 10 minutes quiet on 2 cores, 18 busy.
# Usage: tests/bench/run_estimate_bench.sh [build-dir] [--busy]
set -euo pipefail
build=${1:-build}
busy=${2:-}
wavecam="$build/plugin/wavecam"
work=$(mktemp -d)
loops=()
cleanup() { for p in "${loops[@]}"; do kill "$p" 2>/dev/null || true; done; rm -rf "$work"; }
trap cleanup EXIT
# a frame with texture and depth: radiance noise over a depth ramp from 2 m to 6 m
frame() {  # NAME WIDTH HEIGHT FOV_DEG
  /usr/bin/python3 - "$work/$1.exr" "$2" "$3" "$4" <<'PY'
import sys
import numpy as np
import OpenImageIO as oiio
path, w, h, fov = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
rng = np.random.default_rng(7)
px = np.zeros((h, w, 4), np.float32)
px[..., :3] = rng.uniform(0.1, 1.0, (h, w, 3))
px[..., 3] = np.linspace(2.0, 6.0, w)[None, :]
spec = oiio.ImageSpec(w, h, 4, "float")
spec.channelnames = ("R", "G", "B", "Z")
spec.attribute("wavecam.fov", fov)
out = oiio.ImageOutput.create(path)
out.open(path, spec)
out.write_image(px)
out.close()
PY
}
seconds() {  # "1h02m", "1m35s", "7s" -> seconds
  python3 -c "import re,sys; t=sys.argv[1]; print(sum(int(n)*{'h':3600,'m':60,'s':1}[u] for n,u in re.findall(r'(\d+)([hms])', t)))" "$1"
}
if [ "$busy" = --busy ]; then
  for _ in 1 2; do (while :; do :; done) & loops+=($!); done
  echo "beside two CPU-bound loops"
fi
frame small 48 32 60
frame medium 64 48 50
lavapipe=/usr/share/vulkan/icd.d/lvp_icd.x86_64.json
printf "%-44s %11s %10s %6s\n" job estimated measured ratio
run() {  # LABEL FRAME FLAGS...
  local label=$1 input="$work/$2.exr"; shift 2
  local line est start end took
  line=$("$wavecam" estimate "$input" "$@" 2>&1 | grep -m1 " terms, about ") || { echo "$label: no estimate"; return; }
  est=$(seconds "$(sed -E 's/.* terms, about ([0-9hms]+) on .*/\1/' <<<"$line")")
  start=$(date +%s.%N)
  "$wavecam" apply "$input" -o "$work/out.exr" "$@" > /dev/null 2>&1
  end=$(date +%s.%N)
  took=$(python3 -c "print(f'{$end - $start:.1f}')")
  python3 -c "
e, m = max($est, 1), $took
flag = '' if 0.5 <= m / e <= 2 else '  (off by more than 2x)'
print(f'{\"$label\":44} {$est:10d}s {m:9.1f}s {m / e:6.2f}{flag}')"
}
run "48x32 60deg random-phase 16 runs, auto" small --method random-phase --runs 16 --wavelengths 3
run "48x32 60deg random-phase 1 run, direct" small --method random-phase --runs 1 --wavelengths 3 --summation direct
run "64x48 50deg random-phase 8 runs, nufft" medium --method random-phase --runs 8 --wavelengths 3 --summation nufft
run "64x48 50deg random-phase 16 runs, kernel" medium --method random-phase --runs 16 --wavelengths 3 --summation kernel
run "48x32 60deg incoherent, auto" small --method incoherent --wavelengths 3
# the GPU rows on Mesa's lavapipe (the Vulkan device on the CPU; a GPU's own rate is measured the same way)
if [ -f "$lavapipe" ]; then
  export VK_ICD_FILENAMES="$lavapipe"
  # (narrower fields than the CPU's rows: lavapipe runs the direct terms about a tenth as fast)
  frame narrow 24 16 20
  frame mid 32 24 30
  run "24x16 20deg random-phase 1 run, direct, gpu" narrow --method random-phase --runs 1 --wavelengths 3 --summation direct --device gpu
  run "32x24 30deg random-phase 16 runs, kernel, gpu" mid --method random-phase --runs 16 --wavelengths 3 --summation kernel --device gpu
  run "48x32 60deg random-phase 16 runs, kernel, gpu" small --method random-phase --runs 16 --wavelengths 3 --summation kernel --device gpu
  unset VK_ICD_FILENAMES
else
  echo "no lavapipe ($lavapipe): the GPU rows left out"
fi
