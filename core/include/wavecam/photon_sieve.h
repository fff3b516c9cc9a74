// A photon sieve (Kipp et al., Nature 414, 184 (2001)): a Fresnel zone plate whose open zones
// are replaced by many round holes centred on those zones, placed at random in azimuth.
//
// The design, for N zones inside an outer radius R (the zone plate's, r_n = R sqrt(n/N)):
//   - the centre zone stays an open disc of radius r_1: its contribution at the focus,
//     |1 - exp(i pi rho^2 / r_1^2)|, is largest at rho = r_1 (a hole on a ring does not apply);
//   - every other open zone n = 3, 5, ... carries one ring of holes, centred at the radius of the
//     zone's mean phase, rho_n = R sqrt((n - 1/2)/N), of diameter d_n = K w_n, w_n = r_n - r_(n-1)
//     the zone's width. K = 1.5 is Kipp's optimum: a hole's field at the focus is
//     pi (d/2)^2 2 J1(pi d / 2w) / (pi d / 2w) (the phase runs pi per zone width across it), whose
//     d-derivative vanishes at pi d / 2w = 2.405 (J0's first zero), d = 1.53 w;
//   - ring n holds M_n = floor(fill 2 pi rho_n / d_n) holes: their diameters cover `fill` of the
//     ring's circumference. The ring is cut into M_n equal sectors, turned by a random angle;
//     each hole lies at a random angle inside its sector, far enough from the sector's edges
//     that it never touches its neighbours (seeded, the same on every machine);
//   - the outermost holes reach past R by up to (K - 1)/2 of a zone width.
// The focus is the zone plate's, r_1^2 / lambda = R^2 / (N lambda).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "wavecam/result.h"

namespace wavecam {

struct SieveDesign {
    int zones = 0;           // N
    double hole_ratio = 1.5;  // K: hole diameter / zone width
    double fill = 0.5;       // share of each ring's circumference covered by hole diameters
    uint32_t seed = 1;
};

// One ring of holes, lengths in units of the outer radius R.
struct SieveRing {
    int zone = 0;              // n, odd, >= 3
    double radius = 0;         // rho_n, the hole centres' radius
    double hole_radius = 0;    // d_n / 2
    long holes = 0;            // M_n
    double rotation = 0;       // start of sector 0, radians
    double margin = 0;         // asin(hole_radius / radius): a hole's half-angle seen from the centre
};

// Radius of the central open disc, r_1 = 1/sqrt(N), in units of R.
double sieve_centre_radius(const SieveDesign& design);
// The ring on open zone n (odd, 3..N), and all of them from the centre out.
SieveRing sieve_ring(const SieveDesign& design, int zone);
std::vector<SieveRing> sieve_rings(const SieveDesign& design);
// Centre angle of hole j of a ring (radians).
double sieve_hole_angle(const SieveDesign& design, const SieveRing& ring, long j);
// Largest K for which no ring of holes reaches its neighbour (or the central disc).
double sieve_max_hole_ratio(int zones);
// Refuses designs that are not a sieve: N < 3 (no ring of holes), K outside (0, Kmax],
// fill outside (0, 90%], a ring left without a hole. Errors start with `field`.
Result<bool> check_sieve(const SieveDesign& design, const std::string& field);

// Every hole in metres for an outer radius R: the central disc first.
struct SieveHole {
    double x, y, radius;
};
std::vector<SieveHole> sieve_holes(const SieveDesign& design, double outer_radius);

// A cell [x0, x1] x [y0, y1] of the aperture plane, metres.
struct ApertureCell {
    double x0, x1, y0, y1;
};

// Area and first moments (integrals of x and y) of the disc of radius a centred on (cx, cy)
// inside `cell`, in closed form.
struct DiscMoments {
    double area = 0, mx = 0, my = 0;
};
DiscMoments disc_in_cell(double cx, double cy, double a, const ApertureCell& cell);

// The sieve of outer radius R in metres: transmission 0/1 at a point, exact open area and
// centroid over a cell (returns the area), total open area, and the smallest hole's diameter.
double sieve_transmission(const SieveDesign& design, double outer_radius, double x, double y);
double sieve_open_area_in_cell(const SieveDesign& design, double outer_radius, const ApertureCell& cell, double& cx,
                               double& cy);
double sieve_area(const SieveDesign& design, double outer_radius);
double sieve_bounding_radius(const SieveDesign& design, double outer_radius);
double sieve_smallest_hole(const SieveDesign& design, double outer_radius);

}  // namespace wavecam
