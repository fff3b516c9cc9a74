#!/usr/bin/env bash
# The main job: installs dependencies, builds wavecam, and images a point source through the
# default (near-optimal) pinhole, writing out/psf.exr and out/psf.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash packaging/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
mkdir -p out
./build/plugin/wavecam psf --pinhole 0.3mm --film-distance 65mm --source-distance inf --source-angle 0deg \
  --wavelength 550nm --film-size 0.6mm --resolution 255 -o out/psf.exr --png out/psf.png
