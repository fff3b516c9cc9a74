#!/usr/bin/env bash
# Installs the build into a temporary prefix and builds a downstream consumer against it with
# find_package(wavecam); or builds the Debian packages (wavecam, wavecam-dev) with CPack, checks
# what each holds and depends on, unpacks both into a scratch root and runs the command,
# oiiotool and OpenImageIO's Python through them, and a downstream build against them.
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
  deb=$(ls "$work"/deb/wavecam_*.deb) dev=$(ls "$work"/deb/wavecam-dev_*.deb)
  [ "$(ls "$work"/deb/*.deb | wc -l)" = 2 ] || { echo "expected two packages: $(ls "$work"/deb)"; exit 1; }
  has() {  # has PACKAGE (yes | no) PATH_REGEX...
    local contents package=$1 want=$2
    contents=$(dpkg-deb -c "$package")
    shift 2
    for f in "$@"; do
      if grep -Eq " $f\$" <<< "$contents"; then found=yes; else found=no; fi
      [ "$found" = "$want" ] || { echo "$(basename "$package"): $f $([ "$want" = yes ] && echo missing || echo present)"; exit 1; }
    done
  }
  lib='./usr/lib(/[a-z0-9_-]+)?'
  runtime=('./usr/bin/wavecam' "$lib/wavecam/wavecam.imageio.so" './usr/share/wavecam/ocio/wavecam.ocio'
           './usr/share/doc/wavecam/copyright' './usr/share/wavecam/blender/wavecam_blender.zip'
           './usr/share/man/man1/wavecam.1.gz' './etc/profile.d/wavecam.sh')
  development=('./usr/include/wavecam/psf.h' './usr/include/wavecam/diffract_image.h'
               "$lib/cmake/wavecam/wavecamConfig.cmake" "$lib/libwavecam.a" "$lib/libwavecam_io.a")
  has "$deb" yes "${runtime[@]}"
  has "$deb" no "${development[@]}" './usr/bin/wavecam-trace'
  has "$dev" yes "${development[@]}"
  has "$dev" no "${runtime[@]}" './usr/bin/wavecam-trace'
  # a runtime user needs runtime libraries only; the tracer's Embree and OpenSubdiv not at all
  depends=$(dpkg-deb -f "$deb" Depends)
  for d in libopenimageio2.4 'libopencolorio[0-9.]+'; do
    grep -Eq "(^|, )$d( |,|$)" <<< "$depends" || { echo "wavecam depends on no $d: $depends"; exit 1; }
  done
  ! grep -Eq -- "-dev|embree|libosd" <<< "$depends" || { echo "wavecam depends on a -dev or tracer package: $depends"; exit 1; }
  grep -q "wavecam (= " <<< "$(dpkg-deb -f "$dev" Depends)" || { echo "wavecam-dev does not depend on wavecam"; exit 1; }

  # installed as a user would, into a scratch root
  root="$work/root"
  mkdir "$root"
  dpkg-deb -x "$deb" "$root"
  dpkg-deb -x "$dev" "$root"
  # the licence: Apache-2.0 for wavecam, and the header-only libraries compiled into it
  copyright="$root/usr/share/doc/wavecam/copyright"
  for line in 'Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/' \
              'Files: \*' 'License: Apache-2.0' 'License: BSD-3-clause' 'License: Expat'; do
    grep -Eq "^$line\$" "$copyright" || { echo "the .deb's copyright lacks '$line'"; exit 1; }
  done
  cmp -s "$copyright" "$src/packaging/copyright" || { echo "the .deb's copyright is not packaging/copyright"; exit 1; }
  # --version, and the man page made from --help with every command's options
  version=$("$root/usr/bin/wavecam" --version)
  [ "$version" = "wavecam $(dpkg-deb -f "$deb" Version)" ] || { echo "wavecam --version: '$version'"; exit 1; }
  zcat "$root/usr/share/man/man1/wavecam.1.gz" | grep -q '^\.SS "wavecam apply"' || { echo "no apply in the man page"; exit 1; }
  zcat "$root/usr/share/man/man1/wavecam.1.gz" | grep -q 'film\\-distance' || { echo "no --film-distance in the man page"; exit 1; }

  oiiotool --pattern constant:color=0.5,0.5,0.5,2 4x4 4 --chnames R,G,B,Z --attrib wavecam.fov 20.0 -d float \
    -o "$work/in.exr"
  "$root/usr/bin/wavecam" apply "$work/in.exr" -o "$work/out.exr" --wavelengths 3 --runs 1 > /dev/null
  used=$(oiiotool --info -v "$work/out.exr" | grep wavecam.colorconfig)
  grep -q "$root/usr/share/wavecam/ocio/wavecam.ocio" <<< "$used" ||
    { echo "the installed command did not find its own config: $used"; exit 1; }

  # oiiotool and OpenImageIO's Python find the plugin through the package's profile.d snippet
  # alone (a login shell's environment, its /usr moved into the scratch root)
  sed "s|/usr/|$root/usr/|g" "$root/etc/profile.d/wavecam.sh" > "$work/profile.sh"
  plain=(env -i PATH=/usr/bin:/bin HOME="$work")
  name="$work/in.exr.wavecam?wavelengths=3"
  ! "${plain[@]}" oiiotool --info "$name" > /dev/null 2>&1 || { echo "oiiotool read $name with no plugin path"; exit 1; }
  "${plain[@]}" sh -c ". '$work/profile.sh'; . '$work/profile.sh'; echo \$OIIO_LIBRARY_PATH" > "$work/path"
  plugin_dir=$(dirname "$(find "$root/usr/lib" -name wavecam.imageio.so)")
  [ "$(cat "$work/path")" = "$plugin_dir" ] ||
    { echo "sourced twice, OIIO_LIBRARY_PATH is $(cat "$work/path"), not the plugin's folder $plugin_dir"; exit 1; }
  "${plain[@]}" sh -c ". '$work/profile.sh'; oiiotool '$name' -o '$work/oiiotool.exr'"
  oiiotool --info -v "$work/oiiotool.exr" | grep -q 'wavecam.pinhole' || { echo "oiiotool did not diffract"; exit 1; }
  "${plain[@]}" sh -c ". '$work/profile.sh'; /usr/bin/python3 -c \"
import OpenImageIO as oiio
buf = oiio.ImageBuf('$name')
assert not buf.has_error, buf.geterror()
print('python: ' + str(buf.spec().width) + 'x' + str(buf.spec().height) + ' pinhole ' + buf.spec().getattribute('wavecam.pinhole'))
\""
  # a downstream project builds against the -dev package in the scratch root
  cmake -S "$src/tests/consumer" -B "$work/consumer" -G Ninja -DCMAKE_PREFIX_PATH="$root/usr" > /dev/null
  cmake --build "$work/consumer" > /dev/null
  "$work/consumer/consumer" | grep "config $root/usr/share/wavecam/ocio/wavecam.ocio" ||
    { echo "the consumer did not use the packaged config"; exit 1; }
  dpkg-deb -f "$deb" Package Version Depends
  dpkg-deb -f "$dev" Package Version Depends
  ;;
esac
