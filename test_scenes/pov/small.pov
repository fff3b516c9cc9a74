// POV-Ray version of scenes/small.toml (same numbers; see wavecam.inc for the conventions).
// render_pov.sh small OUT.exr --width 64 --height 48
#include "wavecam.inc"

camera {
  perspective
  location <0.0, 1.5, 4.0>
  right -x * image_width / image_height  // right-handed (see wavecam.inc)
  up y
  angle 50.0  // horizontal
  look_at <0.0, 0.6, 0.0>
}
Wavecam_Sky(<0.25, 0.45, 0.9>, <0.8, 0.85, 0.95>)

// Ground: checker in (u, v) = (x, -z), one square per metre.
#declare Ground_Pigment = pigment {
  function { 0.75 * Wavecam_Checker_Fn(x, -z, 1) }
  color_map { [0 rgb 0.7] [0.5 rgb 0.7] [0.5 rgb 0.2] [1 rgb 0.2] }
}
plane { y, 0 Wavecam_Paint(Ground_Pigment) }

#declare Ball_Pigment = pigment { rgb <0.8, 0.15, 0.1> }
sphere { <0.3, 0.8, -0.5>, 0.8 Wavecam_Paint(Ball_Pigment) }

Wavecam_Point_Light(<3.0, 6.0, 4.0>, 60 / (6 * 6))
