// POV-Ray version of scenes/default.toml: same camera, lights, planes, cards, spheres and
// boxes, same numbers. Differences (POV-Ray lacks them): the two Catmull-Clark surfaces
// are stand-ins (a superellipsoid for the rounded slab, a torus for the ring), the
// lettering card is plain (no 5x7 font), the sphere's checker follows POV-Ray's uv
// mapping, and light intensities are matched only roughly (no 1/r^2 point-light falloff,
// no sky light). render_pov.sh default OUT.exr --width 256 --height 256
#include "wavecam.inc"

camera {
  perspective
  location <0.0, 0.4, 0.0>
  right -x * image_width / image_height  // right-handed (see wavecam.inc)
  up y
  angle 60.0  // horizontal
  look_at <0.0, 0.4, -10.0>
}
Wavecam_Sky(<0.18, 0.35, 0.85>, <0.75, 0.82, 0.95>)
Wavecam_Area_Light(<-6.0, 12.0, 4.0>, <0.0, 0.0, -12.0>, <12.0, 0.0, 0.0>, <1.1, 1.05, 0.95>)
Wavecam_Point_Light(<3.0, 2.5, 2.0>, <0.4, 0.3, 0.2>)

#declare Ink = <0.02, 0.02, 0.02>;
#declare Card = <0.95, 0.95, 0.95>;

// Ground, 1 m checker in (u, v) = (x, -z).
#declare Ground = pigment {
  function { 0.75 * Wavecam_Checker_Fn(x, -z, 1) }
  color_map { [0 rgb <0.55, 0.55, 0.5>] [0.5 rgb <0.55, 0.55, 0.5>] [0.5 rgb <0.3, 0.3, 0.28>] [1 rgb <0.3, 0.3, 0.28>] }
}
plane { y, 0 Wavecam_Paint(Ground) }

// Back wall at 20 m and the (plain) lettering card.
#declare Wall = pigment { rgb <0.7, 0.62, 0.55> }
#declare Wall_T = Wavecam_Paint(Wall)
Wavecam_Quad(<-16.0, 0.0, -20.0>, <32.0, 0.0, 0.0>, <0.0, 4.0, 0.0>, Wall_T)
#declare Lettering = pigment { rgb <0.95, 0.93, 0.9> }
#declare Lettering_T = Wavecam_Paint(Lettering)
Wavecam_Quad(<-7.5, 2.1, -19.99>, <15.0, 0.0, 0.0>, <0.0, 1.5, 0.0>, Lettering_T)

// Resolution cards at 0.3 m and 12 m, Siemens star at 1 m.
#declare Bars = Wavecam_Ink(Wavecam_Bars_Fn, 4, Card, Ink)
#declare Bars_T = Wavecam_Paint_UV(Bars)
Wavecam_Quad(<-0.16, 0.24, -0.3>, <0.2, 0.0, 0.0>, <0.0, 0.05, 0.0>, Bars_T)
Wavecam_Quad(<-8.0, 0.05, -12.0>, <6.0, 0.0, 0.0>, <0.0, 1.5, 0.0>, Bars_T)
#declare Star = Wavecam_Ink(Wavecam_Star_Fn, 24, Card, Ink)
#declare Star_T = Wavecam_Paint_UV(Star)
Wavecam_Quad(<0.25, 0.62, -1.0>, <0.25, 0.0, 0.0>, <0.0, 0.25, 0.0>, Star_T)

// Stand-in for the rounded slab (cage 2 x 1 x 1 scaled 0.3 at <0.25, -0.02, -1.7>).
#declare Slab = pigment { rgb <0.2, 0.55, 0.3> }
superellipsoid { <0.6, 0.6> scale <0.24, 0.12, 0.12> translate <0.55, 0.13, -1.55> Wavecam_Paint(Slab) }
// Stand-in for the ring (cage of major radius 1, section 0.7, scaled 0.45 at <1.5, 0.16, -4>).
#declare Ring = pigment { rgb <0.85, 0.6, 0.15> }
torus { 0.45, 0.12 translate <1.5, 0.16, -4.0> Wavecam_Paint(Ring) }

// Checkered ball at 6 m.
#declare Ball = Wavecam_Ink(Wavecam_Checker_Fn, 6, <0.85, 0.85, 0.85>, <0.6, 0.05, 0.05>)
sphere { <0.0, 0.6, -6.0>, 0.6 Wavecam_Paint_UV(Ball) }

// Turned crate at 9 m and the octahedron beside it.
#declare Crate = pigment { rgb <0.6, 0.45, 0.3> }
#declare Crate_T = Wavecam_Paint(Crate)
Wavecam_Box(<1.2, 0.0, -9.6>, <2.4, 1.2, -8.4>, 30.0, Crate_T)
#declare Octahedron = pigment { rgb <0.3, 0.4, 0.8> }
#declare Octahedron_T = Wavecam_Paint(Octahedron)
Wavecam_Octahedron(0.4, <0.9, 0.4, -9.0>, Octahedron_T)

// Thin poles, 2 cm wide.
#declare Pole = pigment { rgb 0.9 }
#declare Pole_T = Wavecam_Paint(Pole)
Wavecam_Box(<-0.61, 0.0, -3.01>, <-0.59, 1.5, -2.99>, 0, Pole_T)
Wavecam_Box(<-2.01, 0.0, -7.01>, <-1.99, 2.5, -6.99>, 0, Pole_T)
Wavecam_Box(<3.0, 0.0, -15.01>, <3.02, 3.0, -14.99>, 0, Pole_T)
