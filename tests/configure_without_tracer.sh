#!/usr/bin/env bash
# Configures wavecam with WAVECAM_BUILD_TRACER=OFF and Embree made unfindable, then checks
# that neither Embree nor OpenSubdiv was looked for: the library, the command and the plugin
# need neither. Usage: configure_without_tracer.sh SOURCE_DIR GENERATOR
set -euo pipefail
src=$1 generator=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake -S "$src" -B "$work" -G "$generator" -DWAVECAM_BUILD_TRACER=OFF -DCMAKE_DISABLE_FIND_PACKAGE_embree=ON \
  > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; echo "configure without the tracer failed"; exit 1; }
grep -q "WAVECAM_BUILD_TRACER is OFF" "$work/configure.log" || { echo "the option was not seen"; exit 1; }
if grep -Ei "^(embree_DIR|OPENSUBDIV_[A-Z_]+):" "$work/CMakeCache.txt"; then
  echo "Embree or OpenSubdiv was looked for with the tracer off"; exit 1
fi
targets=$(cmake --build "$work" --target help)
for target in wavecam_core wavecam_io wavecam wavecam_imageio; do
  grep -q "^$target:" <<< "$targets" || { echo "no $target target"; exit 1; }
done
if grep -q "^wavecam_trace" <<< "$targets"; then echo "tracer target present with the tracer off"; exit 1; fi
echo "configured without the tracer: core, io, command and plugin targets present, no Embree or OpenSubdiv"
