#!/usr/bin/env bash
# Runs every libFuzzer harness for RUNS inputs (default 10^6) from an empty corpus plus the
# seeds below; a crash or sanitizer report stops with non-zero status and leaves the input
# (crash-*) in the current folder, to become a regression test.
# Usage: tests/fuzz/run_fuzzers.sh BUILD_DIR [RUNS]
set -euo pipefail
build=$1 runs=${2:-1000000}
seeds=$(mktemp -d)
trap 'rm -rf "$seeds"' EXIT
mkdir -p "$seeds"/{units,settings,description,render}
printf '0.3mm' > "$seeds/units/a"; printf 'inf' > "$seeds/units/b"; printf '50deg' > "$seeds/units/c"
printf 'pinhole=0.2mm\nwavelengths=450nm,550nm,650nm\nruns=4\nmethod=exact\n' > "$seeds/settings/a"
printf 'source = "shot.exr"\npinhole = "0.2mm"\nwavelengths = ["450nm", "550nm"]\nruns = 2\n' > "$seeds/description/a"
head -c 300 /dev/urandom > "$seeds/render/a"
for name in units settings description render; do
  echo "== fuzz_$name: $runs runs"
  "$build/tests/fuzz/fuzz_$name" -runs="$runs" -max_len=512 -print_final_stats=1 "$seeds/$name" 2>&1 |
    grep -E "stat::number_of_executed_units|ERROR|SUMMARY|Done" || true
  [ "${PIPESTATUS[0]}" -eq 0 ] || { echo "fuzz_$name failed"; exit 1; }
done
