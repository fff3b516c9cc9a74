#!/usr/bin/env bash
# The random-phase method's summation measured, whole process, each
# figure from this run:
# Parts 1 to 5 measure the point sums (--summation nufft, the lattice evaluator; part 1 against
# direct), parts 6 to 9 the kernel summation and the defaults (64 runs or more, auto: the kernel summation where it applies).
#   1. 96x96, 1 wavelength, 1 run, 50deg: --summation direct against nufft (goal: direct / nufft >= 80);
#   2. 256x256, 3 wavelengths, 16 runs, default pinhole, 50deg: nufft (goal <= 300 s);
#   3. 1920x1080, 16 wavelengths, 16 runs, 50deg: nufft, the whole job (about 30 minutes here),
#      with the estimate it printed before work.
#   4. noise of 16 random-phase runs: 48x48 uniform grey wall at 2 m, 0.2 mm, f = 50 mm, 3
#      wavelengths, coded and independent phases, per-pixel RMS of (R+G+B) / the convolution
#      method's - 1 over the interior (4 pixels in), and of each channel R, G, B alone, at 5, 10, 20
#      and 50 deg, seeds 1 and 2 (goal at 10 deg: 2% per channel).
#   5. the converged random-phase method against the default: 128x128, 3 wavelengths, 50deg,
#      --method convolution, then random-phase at 16 and 64 runs (64 brings the wall's every channel
#      under 2%); prints each time and 64 runs / convolution (goal <= 30).
#   6. the same frame through --summation kernel (the runs as convolutions with amplitude PSFs):
#      random-phase at 16 and 64 runs, and --method incoherent; then random-phase with every
#      other setting at its default (64 runs, auto); prints each time, the estimate printed before
#      work, and 64 runs / convolution and the default / convolution (goal <= 30).
#   7. part 3's frame and job through --summation kernel (about 5 minutes here; goal 5 minutes), with
#      the convolution method's time on the same frame and the estimate printed before work.
#   8. the paper's method at a wide field: 256x256, 60deg, 0.08 mm, 8 wavelengths, random-phase at
#      its defaults (96 runs, auto: the kernel summation in direction cosines) against the default
#      method on the same frame (goal: <= 30 times), and the job line's choice.
#   9. the same job at 3 wavelengths against the point sums' same runs (--summation nufft, about
#      3 minutes here): relative RMS per channel over the frame (the kernel summation's bound: 1.5%)
#      and the mean's ratio.
# Frames: uniform noise x a checker (radiance), depth from 0.3 m to 20 m (top to bottom).
# Usage: tests/bench/run_summation_bench.sh [build-dir] [part...]
set -euo pipefail
bench_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
build=$(cd "${1:-build}" && pwd)
shift || true
parts=${*:-1 2 3}
wavecam="$build/plugin/wavecam"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

checker=16
source "$bench_dir/bench_frame.sh"
seconds() {
  python3 - "$@" <<'PY'
import subprocess, sys, time
t = time.monotonic()
subprocess.run(sys.argv[1:], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
print(f"{time.monotonic() - t:.2f}")
PY
}
ratio() { python3 -c "print(f'{$1 / $2:.1f}')"; }
noise() {  # noise IMAGE REFERENCE [CHANNEL]: RMS of (R+G+B, or one channel) / the reference's - 1 over the interior, in percent
  local ch=${3:-R,G,B}
  oiiotool "$1" --ch "$ch" --chsum "$2" --ch "$ch" --chsum --div --crop 40x40+4+4 --printstats |
    awk '/Stats Avg/ {a = $3} /Stats StdDev/ {s = $3} END {printf "%.2f", 100 * sqrt(s * s + (a - 1) * (a - 1))}'
}
random_phase="--method random-phase --max-terms 1e15"
random_phase_nufft="$random_phase --summation nufft"

for part in $parts; do
case $part in
1)
  frame 96 96 50.0 f96.exr
  t_nufft=$(seconds "$wavecam" apply f96.exr -o nufft.exr $random_phase_nufft --wavelengths 550nm --runs 1)
  t_direct=$(seconds "$wavecam" apply f96.exr -o direct.exr $random_phase --wavelengths 550nm --runs 1 --summation direct)
  diff=$( (oiiotool nufft.exr direct.exr --diff 2>&1 || true) | sed -n 's/.*Max error  = \([^ ]*\).*/\1/p' | head -1)
  echo "1. 96x96, 1 wavelength, 1 run, 50deg: direct ${t_direct} s, nufft ${t_nufft} s, direct/nufft $(ratio "$t_direct" "$t_nufft") (goal >= 80); largest difference ${diff:-?} (values about 0.5)" ;;
2)
  frame 256 256 50.0 f256.exr
  t=$(seconds "$wavecam" apply f256.exr -o o256.exr $random_phase_nufft --wavelengths 3 --runs 16)
  echo "2. 256x256, 3 wavelengths, 16 runs, 50deg: nufft ${t} s (goal <= 300 s)" ;;
3)
  frame 1920 1080 50.0 f1080.exr
  t=$(seconds "$wavecam" apply f1080.exr -o o1080.exr $random_phase_nufft --wavelengths 16 --runs 16)
  estimate=$("$wavecam" apply f1080.exr -o o1080.exr $random_phase_nufft --wavelengths 16 --runs 16 --max-terms 1 2>&1 |
             sed -n 's/.*, about \([^,]*\) at .*/\1/p' || true)
  echo "3. 1920x1080, 16 wavelengths, 16 runs, 50deg, nufft: the job ${t} s, $(python3 -c "print(f'{$t / 60:.0f}')") min; estimated before work: ${estimate:-?}" ;;
4)
  camera="--pinhole 0.2mm --film-distance 50mm --wavelengths 3"
  for fov in 5 10 20 50; do
    oiiotool --pattern constant:color=0.5,0.5,0.5,2 48x48 4 --chnames R,G,B,Z --attrib wavecam.fov "$fov" \
             -d float -o wall.exr
    "$wavecam" apply wall.exr -o conv.exr $camera >/dev/null 2>&1
    line="4. wall, ${fov}deg, 16 runs:"
    for phases in coded independent; do
      for seed in 1 2; do
        "$wavecam" apply wall.exr -o rp.exr $camera $random_phase_nufft --runs 16 --phases $phases --seed $seed >/dev/null 2>&1
        line="$line $phases seed $seed $(noise rp.exr conv.exr)% (R $(noise rp.exr conv.exr R)%, G $(noise rp.exr conv.exr G)%, B $(noise rp.exr conv.exr B)%);"
      done
    done
    echo "$line"
  done ;;
5)
  frame 128 128 50.0 f128.exr
  t_conv=$(seconds "$wavecam" apply f128.exr -o conv.exr --method convolution --wavelengths 3)
  t16=$(seconds "$wavecam" apply f128.exr -o rp16.exr $random_phase_nufft --wavelengths 3 --runs 16)
  t64=$(seconds "$wavecam" apply f128.exr -o rp64.exr $random_phase_nufft --wavelengths 3 --runs 64)
  echo "5. 128x128, 3 wavelengths, 50deg: convolution ${t_conv} s; random-phase 16 runs ${t16} s, 64 runs ${t64} s; 64 runs / convolution $(ratio "$t64" "$t_conv") (goal <= 30)" ;;
6)
  frame 128 128 50.0 f128.exr
  kernel="--method random-phase --summation kernel --wavelengths 3"
  t_conv=$(seconds "$wavecam" apply f128.exr -o conv.exr --method convolution --wavelengths 3)
  t16=$(seconds "$wavecam" apply f128.exr -o p16.exr $kernel --runs 16)
  t64=$(seconds "$wavecam" apply f128.exr -o p64.exr $kernel --runs 64)
  t_inc=$(seconds "$wavecam" apply f128.exr -o pinc.exr --method incoherent --summation kernel --wavelengths 3)
  t_default=$(seconds "$wavecam" apply f128.exr -o pdef.exr --method random-phase --wavelengths 3)
  estimate=$("$wavecam" apply f128.exr -o p64.exr $kernel --runs 64 --max-terms 1 2>&1 | sed -n 's/.*, about \([^,]*\) at .*/\1/p' || true)
  echo "6. 128x128, 3 wavelengths, 50deg, kernel summation: convolution ${t_conv} s; random-phase 16 runs ${t16} s, 64 runs ${t64} s (estimated ${estimate:-?}); incoherent ${t_inc} s; 64 runs / convolution $(ratio "$t64" "$t_conv") (goal <= 30); random-phase at its defaults (64 runs, auto) ${t_default} s, / convolution $(ratio "$t_default" "$t_conv")" ;;
7)
  frame 1920 1080 50.0 f1080.exr
  kernel="--method random-phase --summation kernel --wavelengths 16 --runs 16"
  t_conv=$(seconds "$wavecam" apply f1080.exr -o conv.exr --method convolution --wavelengths 16)
  t=$(seconds "$wavecam" apply f1080.exr -o p1080.exr $kernel)
  estimate=$("$wavecam" apply f1080.exr -o p1080.exr $kernel --max-terms 1 2>&1 | sed -n 's/.*, about \([^,]*\) at .*/\1/p' || true)
  echo "7. 1920x1080, 16 wavelengths, 16 runs, 50deg, kernel summation: the job ${t} s, $(python3 -c "print(f'{$t / 60:.1f}')") min (goal 5 min; estimated ${estimate:-?}); convolution ${t_conv} s; job / convolution $(ratio "$t" "$t_conv")" ;;
8)
  frame 256 256 60.0 f256.exr
  t_conv=$(seconds "$wavecam" apply f256.exr -o conv.exr --pinhole 0.08mm --wavelengths 8)
  t=$(seconds "$wavecam" apply f256.exr -o paper.exr --method random-phase --pinhole 0.08mm --wavelengths 8)
  chosen=$("$wavecam" estimate f256.exr --method random-phase --pinhole 0.08mm --wavelengths 8 2>&1 | sed -n 's/.*auto summation (\([^;]*\);.*/\1/p' | head -1)
  echo "8. 256x256, 60deg, 0.08 mm, 8 wavelengths: convolution ${t_conv} s; random-phase at its defaults (auto: ${chosen:-?}) ${t} s; / convolution $(ratio "$t" "$t_conv") (goal <= 30)" ;;
9)
  frame 256 256 60.0 f256.exr
  job=(--method random-phase --pinhole 0.08mm --wavelengths 3 --runs 96)
  "$wavecam" apply f256.exr -o auto.exr "${job[@]}" >/dev/null 2>&1
  "$wavecam" apply f256.exr -o sums.exr "${job[@]}" --summation nufft >/dev/null 2>&1
  rms=$(for ch in R G B; do
    oiiotool auto.exr --ch $ch sums.exr --ch $ch --sub --printstats | awk '/Stats Avg/ {a = $3} /Stats StdDev/ {s = $3} END {printf "%.6f %.6f ", a, s}'
    oiiotool sums.exr --ch $ch --printstats | awk '/Stats Avg/ {printf "%.6f\n", $3}'
  done | awk '{printf "%s%.2f%% (mean %+.2f%%)", (NR > 1 ? ", " : ""), 100 * sqrt($1 * $1 + $2 * $2) / $3, 100 * $1 / $3}')
  echo "9. 256x256, 60deg, 0.08 mm, 3 wavelengths, 96 coded runs: auto against the point sums' same runs, RMS per channel R, G, B: ${rms} (bound 1.5%)" ;;
esac
done
