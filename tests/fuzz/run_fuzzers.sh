#!/usr/bin/env bash
# Runs every libFuzzer harness for RUNS inputs (default 10^6) from an empty corpus plus the
# seeds below; a crash or sanitizer report stops with non-zero status and leaves the input
# (crash-*) in the current folder, to become a regression test.
# Usage: tests/fuzz/run_fuzzers.sh BUILD_DIR [RUNS]
set -euo pipefail
build=$1 runs=${2:-1000000}
seeds=$(mktemp -d)
trap 'rm -rf "$seeds"' EXIT
mkdir -p "$seeds"/{units,settings,description,render,job,frames}
printf '0.3mm' > "$seeds/units/a"; printf 'inf' > "$seeds/units/b"; printf '50deg' > "$seeds/units/c"
printf 'pinhole=0.2mm\nwavelengths=450nm,550nm,650nm\nruns=4\nmethod=exact\n' > "$seeds/settings/a"
printf 'source = "shot.exr"\npinhole = "0.2mm"\nwavelengths = ["450nm", "550nm"]\nruns = 2\n' > "$seeds/description/a"
head -c 300 /dev/urandom > "$seeds/render/a"
printf '1-100000000' > "$seeds/frames/a"; printf '3,7,10-20x2,1-9y3' > "$seeds/frames/b"
# job: width, height (bytes), fov and depth (little-endian floats), flags (1: fov as a string,
# 2: settings as text lines, else byte pairs choosing keys and extreme values), then settings; the seeds are the hostile cases of tests/fronts/test_apply_hostile.cpp (python3 packs the floats)
job_seed() {  # NAME W H FOV DEPTH SETTINGS
  python3 -c 'import struct,sys; sys.stdout.buffer.write(bytes([int(sys.argv[1]), int(sys.argv[2])]) +
struct.pack("<ff", float(sys.argv[3]), float(sys.argv[4])) + b"\2" + sys.argv[5].encode())' \
    "$2" "$3" "$4" "$5" "$6" > "$seeds/job/$1"
}
job_seed a 16 16 30 2 $'pinhole=1000m\n'
job_seed b 16 16 30 2 $'pinhole=1nm\nmethod=exact\n'
job_seed c 2 128 30 2 ''
job_seed d 16 16 1e-30 2 ''
job_seed e 16 16 179.999 2 ''
job_seed f 16 16 30 1e-40 $'film-distance=1000m\n'
job_seed g 16 16 30 1e-6 $'wavelengths=450nm,550nm\nruns=100000\nmethod=incoherent\n'
printf '\x10\x10\x00\x00\xf0\x41\x00\x00\x00\x40\x00\x00\x06\x01\x03\x08\x01' > "$seeds/job/h"  # byte pairs
for name in units settings description render job frames; do
  echo "== fuzz_$name: $runs runs"
  # -timeout: an input that takes 30 s (a hang before the work; ASan runs ~20x slower than a
  # release build) is a finding, as a crash is
  "$build/tests/fuzz/fuzz_$name" -runs="$runs" -max_len=512 -timeout=30 -print_final_stats=1 "$seeds/$name" 2>&1 |
    grep -E "stat::number_of_executed_units|ERROR|SUMMARY|Done" || true
  [ "${PIPESTATUS[0]}" -eq 0 ] || { echo "fuzz_$name failed"; exit 1; }
done
