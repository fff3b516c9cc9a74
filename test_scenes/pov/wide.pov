// POV-Ray version of scenes/wide.toml: same camera (136.4 degree horizontal field), light,
// cards, spheres and boxes, same numbers. Differences (POV-Ray lacks them): the two
// Catmull-Clark surfaces are stand-ins (a torus for the ring, a superellipsoid for the
// rounded cube), the lettering card is plain (no 5x7 font), the sphere's checker follows
// POV-Ray's uv mapping, and the light is matched only roughly (no sky light; POV-Ray
// shades an area light by its centre, so the on-axis star, whose plane has the panel's
// centre behind it, stays dark).
// render_pov.sh wide OUT.exr --width 400 --height 160
#include "wavecam.inc"

camera {
  perspective
  location <0.0, 1.0, 0.0>
  right -x * image_width / image_height  // right-handed (see wavecam.inc)
  up y
  angle 136.397181  // horizontal
  look_at <0.0, 1.0, -10.0>
}
Wavecam_Sky(<0.2, 0.38, 0.85>, <0.78, 0.84, 0.95>)
Wavecam_Area_Light(<-8.0, 10.0, 4.0>, <0.0, 0.0, -16.0>, <16.0, 0.0, 0.0>, <0.75, 0.72, 0.65>)

#declare Ink = <0.02, 0.02, 0.02>;
#declare Card = <0.95, 0.95, 0.95>;
#declare Ground = pigment {
  function { 0.75 * Wavecam_Checker_Fn(x, -z, 1) }
  color_map { [0 rgb <0.55, 0.55, 0.5>] [0.5 rgb <0.55, 0.55, 0.5>] [0.5 rgb <0.3, 0.3, 0.28>] [1 rgb <0.3, 0.3, 0.28>] }
}
plane { y, 0 Wavecam_Paint(Ground) }
#declare Star = Wavecam_Ink(Wavecam_Star_Fn, 24, Card, Ink)
#declare Star_T = Wavecam_Paint_UV(Star)
#declare Bars = Wavecam_Ink(Wavecam_Bars_Fn, 4, Card, Ink)
#declare Bars_T = Wavecam_Paint_UV(Bars)
#declare Lettering = pigment { rgb <0.95, 0.93, 0.9> }
#declare Lettering_T = Wavecam_Paint(Lettering)
#declare Ring = pigment { rgb <0.85, 0.6, 0.15> }
#declare Cube = pigment { rgb <0.2, 0.55, 0.3> }
#declare Ball = Wavecam_Ink(Wavecam_Checker_Fn, 6, <0.85, 0.85, 0.85>, <0.6, 0.05, 0.05>)
#declare Blue = pigment { rgb <0.3, 0.4, 0.85> }
#declare Crate = pigment { rgb <0.6, 0.45, 0.3> }
#declare Crate_T = Wavecam_Paint(Crate)
#declare Pole = pigment { rgb 0.9 }
#declare Pole_T = Wavecam_Paint(Pole)

Wavecam_Quad(<-0.3, 0.7, -3.0>, <0.6, 0.0, 0.0>, <0.0, 0.6, 0.0>, Star_T)
Wavecam_Quad(<-2.7481, 0.7, -1.2402>, <0.3, 0.0, -0.5196>, <0.0, 0.6, 0.0>, Star_T)
Wavecam_Quad(<2.4481, 0.7, -1.7598>, <0.3, 0.0, 0.5196>, <0.0, 0.6, 0.0>, Star_T)
Wavecam_Quad(<-3.366, 0.5, -3.8301>, <1.7321, 0.0, -1.0>, <0.0, 0.5, 0.0>, Bars_T)
Wavecam_Quad(<1.634, 0.5, -4.8301>, <1.7321, 0.0, 1.0>, <0.0, 0.5, 0.0>, Bars_T)
Wavecam_Quad(<-4.5, 2.2, -15.0>, <9.0, 0.0, 0.0>, <0.0, 1.35, 0.0>, Lettering_T)
// Stand-in for the ring (cage of major radius 1, section 0.7, scaled 0.4)
torus { 0.400, 0.108 translate <1.7678, 0.14, -1.7678> Wavecam_Paint(Ring) }
// Stand-in for the rounded cube (unit cage scaled 0.6 at <-1.7678, -0.03, -1.7678>)
superellipsoid { <0.6, 0.6> scale 0.240 translate <-1.4678, 0.27, -1.4678> Wavecam_Paint(Cube) }
sphere { <-2.0706, 0.8, -7.7274>, 0.8 Wavecam_Paint_UV(Ball) }
sphere { <0.3106, 0.25, -1.1591>, 0.25 Wavecam_Paint(Blue) }
Wavecam_Box(<3.36, 0.0, -1.54>, <4.36, 1.0, -0.54>, 20.0, Crate_T)
Wavecam_Box(<-6.3, 0.0, -2.05>, <-5.3, 1.5, -1.05>, -10.0, Crate_T)
Wavecam_Box(<-1.4017, 0.0, -9.9127>, <-1.3817, 2.5, -9.8927>, 0.0, Pole_T)
