#!/usr/bin/env bash
# render_pov.sh SCENE.pov|SCENE.ini OUT.exr [--width W --height H] [--fov DEG] [--depth-scale 1cm]
#               [--frames A-B] [POV-Ray options: +Q5 Declare=NAME=VALUE +KI0 +KF2 user.ini ...]
#
# Renders an unmodified POV-Ray 3.7 scene into the EXR wavecam takes: R, G, B (POV-Ray's own
# render, linear), Z (planar depth, 1e10 = sky; metres with --depth-scale, else scene units) and
# wavecam.fov (horizontal, degrees). SCENE is a .pov file (any case), an .ini naming one, or a
# name under test_scenes/pov (small, default, wide). With --frames, OUT is a pattern (out.#.exr).
# How: render_pov.py; docs/povray.md.
set -euo pipefail
for tool in povray /usr/bin/python3; do
  command -v "$tool" >/dev/null || { echo "render_pov.sh: $tool not found (packaging/install-deps.sh)" >&2; exit 1; }
done
# Debian's python3 (python3-openimageio, python3-numpy), whatever python3 is first on PATH.
exec /usr/bin/python3 -B "$(dirname "${BASH_SOURCE[0]}")/render_pov.py" "$@"
