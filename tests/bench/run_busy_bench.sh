#!/usr/bin/env bash
# wavecam on a busy machine, each figure a ratio within this run:
#   1. a scene-sum job (32x32, 3 wavelengths, 4 random-phase runs, nufft) beside two CPU-bound
#      loops, against a fair share of the machine: twice its quiet time on 2 cores (goal <= 1.4);
#   2. the same job while Blender renders the next frame (Cycles on the CPU, every core, as
#      Blender renders with its window): run as the add-on runs it there (nice 10, below
#      Blender's priority) and at Blender's own priority. Printed: the job's time against a fair
#      share, and Blender's render time against its time alone (nice 10 should cost Blender little).
# Needs Debian's blender. About 4 minutes on 2 cores.
# Usage: tests/bench/run_busy_bench.sh [build-dir]
set -euo pipefail
bench_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
build=$(cd "${1:-build}" && pwd)
wavecam="$build/plugin/wavecam"
work=$(mktemp -d)
loops=()
trap 'kill "${loops[@]}" 2>/dev/null || true; rm -rf "$work"' EXIT
cd "$work"
source "$bench_dir/bench_frame.sh"
frame 32 32 50.0 f32.exr
job=("$wavecam" apply f32.exr -o o32.exr --method random-phase --runs 4 --summation nufft --wavelengths 3)

now() { date +%s.%N; }
since() { python3 -c "print(f'{$(now) - $1:.2f}')"; }
ratio() { python3 -c "print(f'{($1) / ($2):.2f}')"; }

# Blender's frames: the default scene through Cycles at 640x360, 300 samples each (about 16 s a
# frame alone); three of them, so that Blender is still rendering when the job ends
cat > scene.py <<'PY'
import bpy
s = bpy.context.scene
s.render.engine = 'CYCLES'
s.cycles.device = 'CPU'
s.cycles.samples = 300
s.cycles.use_adaptive_sampling = False  # every pixel all its samples: a steady load
s.cycles.use_denoising = False  # Debian's build has no OpenImageDenoise
s.render.resolution_x, s.render.resolution_y = 640, 360
s.render.image_settings.file_format = 'OPEN_EXR'
s.render.filepath = '//frame_'
PY
render() { blender -b --factory-startup --python scene.py -s 1 -e 3 -a > blender.log 2>&1; now > blender.end; }

start=$(now); "${job[@]}" > /dev/null 2>&1; quiet=$(since "$start")
start=$(now); render; blender_alone=$(since "$start")
echo "quiet: the job ${quiet} s; Blender's three frames alone ${blender_alone} s"

for _ in 1 2; do (while :; do :; done) & loops+=($!); done
start=$(now); "${job[@]}" > /dev/null 2>&1; t=$(since "$start")
kill "${loops[@]}"; wait "${loops[@]}" 2>/dev/null || true; loops=()
echo "1. beside two busy loops: ${t} s, $(ratio "$t" "2 * $quiet") of a fair share (goal <= 1.4)"

for nice in 10 0; do
  start=$(now); render & blender_pid=$!
  sleep 3  # Blender started and rendering
  job_start=$(now); nice -n $nice "${job[@]}" > /dev/null 2>&1; t=$(since "$job_start")
  wait $blender_pid
  blender_took=$(python3 -c "print(f'{$(cat blender.end) - $start:.2f}')")
  echo "2. beside Blender rendering, nice $nice: the job ${t} s, $(ratio "$t" "2 * $quiet") of a fair share;" \
       "Blender's frames ${blender_took} s, $(ratio "$blender_took" "$blender_alone") of their time alone"
done
