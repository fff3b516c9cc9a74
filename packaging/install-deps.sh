#!/usr/bin/env bash
# Installs everything wavecam needs to build, test and run on Debian bookworm.
# Idempotent: when every package is present it only checks (dpkg-query) and exits.
set -euo pipefail

PACKAGES=(
  # toolchain
  g++ cmake ninja-build pkg-config git
  # image I/O and colour (the user's fixed stack)
  libopenimageio-dev openimageio-tools python3-openimageio
  libopencolorio-dev opencolorio-tools libopenexr-dev
  # test-scene tracer
  libembree-dev libosd-dev
  # chosen dependencies (see README, "Dependencies")
  libcli11-dev libtomlplusplus-dev libeigen3-dev
  # packaging (.deb with shared-library dependencies; the man page made from --help)
  dpkg-dev file help2man
  # tests and benchmarks
  libgtest-dev libbenchmark-dev
  # the Vulkan evaluator of the point sums: the loader and headers, glslc for its shaders, and
  # Mesa's lavapipe, the Vulkan device on the CPU its tests run on (vulkaninfo to look at devices)
  libvulkan-dev glslc mesa-vulkan-drivers vulkan-tools
  # labels on contact sheets (OIIO render_text)
  fonts-dejavu-core
  # POV-Ray renders (render_pov.sh: Debian's python3 with OIIO and numpy; tests read the
  # shipped example scenes)
  povray povray-includes povray-examples python3-numpy
  # the Blender add-on's tests (headless Cycles renders; the add-on tags EXRs through OIIO's
  # Python; its UI test runs Blender in a virtual X server)
  blender xvfb xauth
  # wavecam farm's test: a one-node Slurm cluster (tests/slurm_cluster.sh)
  slurm-wlm munge
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
