#!/usr/bin/env bash
# render_pov.sh SCENE OUT.exr
#
# Renders a test scene with POV-Ray into the EXR layout wavecam-trace writes: float R, G, B
# (radiance) and Z (planar depth, metres, 1e10 = sky) with the header attributes
# wavecam.fov, wavecam.depth = "planar", wavecam.scene and worldToCamera.
# SCENE is a name under test_scenes/pov (small, default, wide) or a path to a .pov file.
#
# Two POV-Ray runs: the radiance pass (antialiased), and a depth pass without lights or
# antialiasing in which every surface emits min(planar depth, 1000 m) / 1000 m. POV-Ray
# writes half-float EXR, so depth keeps about 3 significant digits (relative step 2^-11 ~
# 4.9e-4, rounding error half that); depths >= 1000 m read as sky. oiiotool merges the passes.
set -euo pipefail

if [ $# -ne 2 ]; then
  echo "usage: render_pov.sh SCENE OUT.exr" >&2
  exit 2
fi
pov_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
scene=$1
[[ $scene == *.pov ]] || scene="$pov_dir/$scene.pov"
if [ ! -f "$scene" ]; then
  echo "render_pov.sh: $scene: no such POV-Ray scene" >&2
  exit 1
fi
scene=$(realpath "$scene")
out=$(realpath -m "$2")
for tool in povray oiiotool; do
  command -v "$tool" >/dev/null || { echo "render_pov.sh: $tool not found" >&2; exit 1; }
done

size() { sed -n "s/^#declare Wavecam_$1 *= *\([0-9]*\);.*/\1/p" "$scene"; }
width=$(size Width)
height=$(size Height)
if [ -z "$width" ] || [ -z "$height" ]; then
  echo "render_pov.sh: $scene: no '#declare Wavecam_Width/Height = N;' lines" >&2
  exit 1
fi

# POV-Ray's I/O security (/etc/povray/3.7/povray.conf, "restricted") reads the current
# directory and writes /tmp: run from the scene's folder with outputs under /tmp.
tmp=$(mktemp -d /tmp/render_pov.XXXXXX)
partial="$(dirname "$out")/.$(basename "$out").partial.exr"
trap 'rm -rf "$tmp" "$partial"' EXIT
cd "$(dirname "$scene")"

pov() {  # pov LOG OPTIONS...
  local log=$1
  shift
  if ! povray -D +I"$scene" +FE +W"$width" +H"$height" "$@" >"$log" 2>&1; then
    echo "render_pov.sh: povray failed on $scene:" >&2
    grep -i -A3 "error" "$log" >&2 || tail -5 "$log" >&2
    exit 1
  fi
}
pov "$tmp/radiance.log" +O"$tmp/radiance.exr" +A0.02 +AM2 +R3
pov "$tmp/depth.log" +O"$tmp/depth.exr" -A Declare=Wavecam_Depth_Pass=1

attr() { sed -n "s/^wavecam-attr $1 //p" "$tmp/radiance.log" | head -1; }
fov=$(attr fov)
world_to_camera="$(attr worldToCamera0),$(attr worldToCamera1),$(attr worldToCamera2),$(attr worldToCamera3)"
scene_name=$(attr scene)

# Z = max(1000 v, 1e10 [v >= 0.9999]): the step is (v - 0.9999) * 1e8 clamped to [0, 1]
# (the largest half below 1 is 0.99951), so sky and clamped surfaces become exactly 1e10.
oiiotool "$tmp/radiance.exr" --ch R,G,B -d float \
  "$tmp/depth.exr" --ch R -d float --dup --mulc 1000 --swap \
  --subc 0.9999 --mulc 1e8 --clamp:min=0:max=1 --mulc 1e10 --max --chnames Z \
  --chappend \
  --attrib:type=float wavecam.fov "$fov" \
  --attrib wavecam.depth planar \
  --attrib wavecam.scene "$scene_name" \
  --attrib:type=matrix worldToCamera "$world_to_camera" \
  --compression zip -d float -o "$partial"
mv "$partial" "$out"
