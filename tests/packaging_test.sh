#!/usr/bin/env bash
# Installs the build into a temporary prefix and builds a downstream consumer against it with
# find_package(wavecam); then builds the .deb with CPack and checks its contents.
# Usage: packaging_test.sh SOURCE_DIR BUILD_DIR (install | deb)
set -euo pipefail
src=$1 build=$2 what=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
case "$what" in
install)
  cmake --install "$build" --prefix "$work/prefix" > /dev/null
  cmake -S "$src/tests/consumer" -B "$work/consumer" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" > /dev/null
  cmake --build "$work/consumer" > /dev/null
  out=$("$work/consumer/consumer")
  echo "$out"
  # the consumer must find the installed config, not the source tree's
  grep -q "optimal pinhole 0.3151 mm; config $work/prefix/share/wavecam/ocio/wavecam.ocio" <<< "$out" ||
    { echo "consumer did not use the installed config"; exit 1; }
  ;;
deb)
  (cd "$build" && cpack -G DEB -B "$work/deb" > /dev/null)
  deb=$(ls "$work"/deb/*.deb)
  contents=$(dpkg-deb -c "$deb")
  for f in './usr/bin/wavecam' './usr/lib(/[a-z0-9_-]+)?/wavecam/wavecam.imageio.so' \
           './usr/share/wavecam/ocio/wavecam.ocio' './usr/include/wavecam/psf.h' './usr/include/wavecam/diffract_image.h' \
           './usr/lib(/[a-z0-9_-]+)?/cmake/wavecam/wavecamConfig.cmake' './usr/lib(/[a-z0-9_-]+)?/libwavecam.a' \
           './usr/share/doc/wavecam/copyright' './usr/share/wavecam/blender/wavecam_blender.zip'; do
    grep -Eq " $f\$" <<< "$contents" || { echo "missing from the .deb: $f"; exit 1; }
  done
  # installed as a user would: the command and the plugin find their own config
  mkdir "$work/root"
  dpkg-deb -x "$deb" "$work/root"
  # the licence: Apache-2.0 for wavecam, and the header-only libraries compiled into it
  copyright="$work/root/usr/share/doc/wavecam/copyright"
  for line in 'Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/' \
              'Files: \*' 'License: Apache-2.0' 'License: BSD-3-clause' 'License: Expat'; do
    grep -Eq "^$line\$" "$copyright" || { echo "the .deb's copyright lacks '$line'"; exit 1; }
  done
  cmp -s "$copyright" "$src/packaging/copyright" || { echo "the .deb's copyright is not packaging/copyright"; exit 1; }
  oiiotool --pattern constant:color=0.5,0.5,0.5,2 4x4 4 --chnames R,G,B,Z --attrib wavecam.fov 20.0 -d float \
    -o "$work/in.exr"
  "$work/root/usr/bin/wavecam" apply "$work/in.exr" -o "$work/out.exr" --wavelengths 3 --runs 1 > /dev/null
  used=$(oiiotool --info -v "$work/out.exr" | grep wavecam.colorconfig)
  grep -q "$work/root/usr/share/wavecam/ocio/wavecam.ocio" <<< "$used" ||
    { echo "the installed command did not find its own config: $used"; exit 1; }
  dpkg-deb -f "$deb" Package Version Depends
  ;;
esac
