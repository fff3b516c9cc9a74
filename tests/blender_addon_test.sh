#!/usr/bin/env bash
# The Blender add-on in Debian's Blender, headless, as a user runs it: installed from the zip
# into temporary BLENDER_USER_* folders, a tiny Cycles scene rendered with `-a` or `-f N`.
# Usage: blender_addon_test.sh SOURCE_DIR BUILD_DIR (animation | portrait | errors | settings | oldfile | ui)
# ui: Blender with its UI under xvfb-run (exit 77, skipped, where xvfb-run is missing);
# WAVECAM_UI_SCREENSHOTS=DIR keeps its screenshots there.
set -euo pipefail
src=$1 build=$2 what=$3
[ "$what" = ui ] && ! command -v xvfb-run > /dev/null && { echo "xvfb-run not installed: skipped"; exit 77; }
steps="$src/tests/blender/addon_steps.py"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export BLENDER_USER_CONFIG="$work/config" BLENDER_USER_SCRIPTS="$work/scripts"
blender=(blender -b --python-exit-code 1)
"${blender[@]}" --python "$steps" -- install "$build/plugin/blender/wavecam_blender.zip" "$build/plugin/wavecam" \
  > "$work/install.log" 2>&1 || { cat "$work/install.log"; exit 1; }
shape=landscape
[ "$what" = portrait ] && shape=portrait
"${blender[@]}" --python "$steps" -- scene "$work/scene.blend" "$work/frame_" "$shape" > "$work/scene.log" 2>&1 ||
  { cat "$work/scene.log"; exit 1; }
case "$what" in
animation)
  blender -b "$work/scene.blend" -a > "$work/render.log" 2>&1 || { cat "$work/render.log"; exit 1; }
  grep "wavecam" "$work/render.log"
  "${blender[@]}" "$work/scene.blend" --python "$steps" -- check 1 2 2>&1 | grep -E "^(frame|FAIL|Error|Trace)|check"
  ;;
portrait)  # sensor fit Auto, then Vertical
  for blend in scene scene_vertical; do
    blender -b "$work/$blend.blend" -f 1 > "$work/render.log" 2>&1 || { cat "$work/render.log"; exit 1; }
    grep "wavecam" "$work/render.log"
    "${blender[@]}" "$work/$blend.blend" --python "$steps" -- check 1 2>&1 | grep -E "^(frame|FAIL|Error|Trace)|check"
  done
  ;;
errors)
  "${blender[@]}" "$work/scene.blend" --python "$steps" -- errors > "$work/errors.log" 2>&1 ||
    { cat "$work/errors.log"; exit 1; }
  for expected in "this render is not diffracted: camera 'Camera' has shift" "wavecam command was not found" \
                  "Wavelength list: 'banana' is not a wavelength" "has no Z pass"; do
    grep -F -- "wavecam: error: " "$work/errors.log" | grep -qF -- "$expected" ||
      { cat "$work/errors.log"; echo "no reported error containing: $expected"; exit 1; }
  done
  grep -E "^wavecam: " "$work/errors.log"
  ;;
settings)
  "${blender[@]}" "$work/scene.blend" --python "$steps" -- settings > "$work/settings.log" 2>&1 ||
    { cat "$work/settings.log"; exit 1; }
  grep -E "^(pinhole|film|tooltips|images|orthographic|panoramic|png|max_terms|gpu_nufft|software|decreasing|xray|wavelengths0|runs0|centimetres|vignetting|summation|estimate)" \
    "$work/settings.log"
  ;;
oldfile)  # saved without the add-on, as its earlier version did; loaded with it
  "${blender[@]}" --factory-startup --python "$steps" -- oldfile "$work/old.blend" > "$work/old.log" 2>&1 ||
    { cat "$work/old.log"; exit 1; }
  "${blender[@]}" "$work/old.blend" --python "$steps" -- loadold 2>&1 | grep -E "^(old file|FAIL|Error|Trace)"
  ;;
ui)
  timeout 280 xvfb-run -a -s "-screen 0 1280x800x24" blender --enable-event-simulate "$work/scene.blend" \
    --python "$src/tests/blender/ui_steps.py" > "$work/ui.log" 2>&1 || { cat "$work/ui.log"; exit 1; }
  grep -E "^(wavecam|Info|F12|Ctrl|ui:)" "$work/ui.log"
  ! grep -B2 -A12 "^Traceback" "$work/ui.log" || { echo "a Python error in Blender's UI"; exit 1; }
  ;;
esac
