#!/usr/bin/env bash
# The default job (the convolution method, 16 wavelengths) on a 1920x1080 frame at 50 and 100 deg
# and on the main job's 512x512 frame at 60 deg with its "too small" 0.08 mm pinhole, this build
# against a baseline build of another commit, run in turn (A B A B ...) and compared pair by
# pair: the median time of each and the median of the pairs' ratios.
# Usage: tests/bench/run_vs_baseline.sh BUILD BASELINE_BUILD [runs]
set -euo pipefail
bench_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
new=$(cd "$1" && pwd)/plugin/wavecam
old=$(cd "$2" && pwd)/plugin/wavecam
runs=${3:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

source "$bench_dir/bench_frame.sh"

paired() {  # paired LABEL ARGS...: A and B in turn, the medians and the median ratio
  local label=$1
  shift
  python3 - "$new" "$old" "$runs" "$label" "$@" <<'PY'
import statistics, subprocess, sys, time
new, old, runs, label, args = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5:]
def t(binary):
    s = time.monotonic()
    subprocess.run([binary] + args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.monotonic() - s
t(new); t(old)  # warm the caches
a, b = [], []
for _ in range(runs):
    a.append(t(new)); b.append(t(old))
print(f"{label}: this build {statistics.median(a):.2f} s, baseline {statistics.median(b):.2f} s, "
      f"ratio {statistics.median(x / y for x, y in zip(a, b)):.2f} (min {min(x / y for x, y in zip(a, b)):.2f}, "
      f"max {max(x / y for x, y in zip(a, b)):.2f})")
PY
}

frame 1920 1080 50.0 f50.exr
frame 1920 1080 100.0 f100.exr
frame 512 512 60.0 f512.exr
paired "1920x1080, 50deg, defaults, 16 wavelengths" apply f50.exr -o o.exr --wavelengths 16
paired "1920x1080, 100deg, defaults, 16 wavelengths" apply f100.exr -o o.exr --wavelengths 16
paired "512x512, 60deg, 0.08mm, 16 wavelengths" apply f512.exr -o o.exr --wavelengths 16 --pinhole 0.08mm
