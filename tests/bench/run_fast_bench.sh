#!/usr/bin/env bash
# The fast path against the practical alternative, in one run: `wavecam apply` (fast method,
# 16 wavelengths) on a 1920x1080 RGB+Z EXR with depth from 0.3 m to 20 m and a wide field,
# against `oiiotool --convolve` of the same RGB with one 65x65 kernel. Prints wall time and
# peak memory of each, and the ratio last.
# Usage: tests/bench/run_fast_bench.sh [build-dir]
set -euo pipefail
build=$(cd "${1:-build}" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
oiiotool --pattern noise:type=uniform:min=0:max=1 1920x1080 3 --chnames R,G,B \
         --pattern checker:width=64:height=64:color1=0.2,0.2,0.2:color2=1,1,1 1920x1080 3 --mul \
         --pattern fill:top=0.3:bottom=20 1920x1080 1 --chnames Z --chappend \
         --attrib wavecam.fov 100.0 -d float -o frame.exr
oiiotool frame.exr --ch R,G,B -o rgb.exr

# seconds and peak resident memory (MiB) of a command
measure() {
  python3 - "$@" <<'PY'
import resource, subprocess, sys, time
t = time.monotonic()
subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL)
dt = time.monotonic() - t
print(f"{dt:.2f} {resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024:.0f}")
PY
}
read -r t_oiio m_oiio < <(measure oiiotool rgb.exr --kernel gaussian 65x65 --convolve -o conv.exr)
echo "oiiotool --convolve 65x65      : ${t_oiio} s, peak ${m_oiio} MiB"
read -r t_wave m_wave < <(measure "$build/plugin/wavecam" apply frame.exr -o wave.exr --wavelengths 16)
echo "wavecam apply (fast, 16 lambda): ${t_wave} s, peak ${m_wave} MiB"
python3 -c "print(f'ratio wavecam / oiiotool: {$t_wave / $t_oiio:.2f} (goal <= 0.5)')"
