// The pinhole: an opening in the plane z = 0 centred on the origin, and its sampling.
//
// Shapes (all sized by `diameter`, metres):
//   circle          a disc of that diameter;
//   square          a square of that side, edges along x and y;
//   polygon:N[:R]   a regular N-gon inscribed in a circle of that diameter, a vertex at angle R
//                   from +x (R = 0: a vertex on +x);
//   mask:FILE       a greyscale image of amplitude transmission 0..1, its width spanning the
//                   diameter, square pixels (a non-square image keeps its aspect), centred;
//   zoneplate:N     a Fresnel zone plate of N zones inside that diameter: zone n spans
//                   r_(n-1) < r < r_n, r_n = (D/2) sqrt(n/N), odd zones (the centre) open.
//                   Its first focus is at r_1^2 / lambda (Born & Wolf 8.8.4; Hecht 10.3.5).
//   sieve:N[:Kx][:FILL%][:SEED]
//                   a photon sieve: that zone plate's open zones 3, 5, ... replaced by rings of
//                   round holes K zone widths wide (1.5x), their diameters covering FILL of each
//                   ring (50%), at seeded random angles (seed 1); the centre zone stays open.
//                   Same focus as the zone plate (wavecam/photon_sieve.h has the design).
// Coordinates: x toward the render's right, y toward its top - the pinhole as seen from behind,
// from the film looking out at the scene. A point's blur on the upright output image is the
// aperture's shadow rotated by 180 degrees, as on a real camera's print.
#pragma once
#include <cstddef>
#include <memory>
#include <string>
#include <vector>
#include "wavecam/photon_sieve.h"
#include "wavecam/result.h"

namespace wavecam {

enum class ApertureShape { Circle, Square, Polygon, Mask, ZonePlate, PhotonSieve };

// A sampled transmission image: row 0 at the top (+y), column 0 at the left (-x).
struct TransmissionMask {
    int width = 0, height = 0;
    std::vector<float> amplitude;  // row-major, 0..1
    double radius = 0;             // largest distance of an open pixel's corner from the centre, in mask widths
};

struct Aperture {
    ApertureShape shape = ApertureShape::Circle;
    double diameter = 0.0;  // metres; the side for a square, the circumscribed diameter for a polygon
    int sides = 0;          // polygon
    double rotation = 0.0;  // polygon: angle of a vertex from +x, radians
    int zones = 0;          // zone plate, photon sieve
    double hole_ratio = 1.5;  // photon sieve: hole diameter / zone width
    double fill = 0.5;        // photon sieve: share of each ring's circumference the holes cover
    uint32_t seed = 1;        // photon sieve: the holes' random angles
    std::shared_ptr<const TransmissionMask> mask{};  // {}: `{shape, diameter}` initialises every member
    std::string mask_file{};  // as given, for headers and messages

    // Amplitude transmission at (x, y): 0 or 1 for the hard-edged shapes, 0..1 for a mask.
    double transmission(double x, double y) const;
    bool contains(double x, double y) const { return transmission(x, y) > 0; }
    // Mean amplitude transmission over the axis-aligned cell [x0,x1]x[y0,y1] and the centroid of
    // the transmission there (16 x 16 sub-cells on the rim; exact box integrals for a mask).
    double coverage(double x0, double x1, double y0, double y1, double& cx, double& cy) const;
    // Power transmitted per unit irradiance: the integral of |t|^2 (the open area for a hard edge).
    double area() const;
    // Radius of the smallest centred disc holding every open point.
    double bounding_radius() const;
    // Whether the transmission is even in x, t(-x, y) = t(x, y) (or in y): the whole camera is
    // then a mirror image of itself, and the PSF at field (-u, v) the mirror image of the one at
    // (u, v). A photon sieve's random hole angles are neither.
    bool even_in_x() const;
    bool even_in_y() const;
    // Whether the transmission is its own mirror image across the line y = -x, t(-y, -x) = t(x, y):
    // a square frame's camera then turns pixel (i, j) into (j, i) (image rows point down), and the
    // PSF at field (-v, -u) is the transpose of the one at (u, v).
    bool even_across_antidiagonal() const;
    // Width of the narrowest opening the samples must resolve: a sieve's smallest hole, a zone
    // plate's narrowest open zone, else the diameter.
    double finest_width() const;
    SieveDesign sieve() const { return {zones, hole_ratio, fill, seed}; }
    // Text that names the aperture as --aperture takes it, e.g. "polygon:6:0deg".
    std::string name() const;
};

// A zone plate's (or photon sieve's) first focus for a plane wave: r_1^2 / lambda,
// r_1 = (D/2) / sqrt(N) (paraxial).
double zone_plate_focus(const Aperture& zone_plate, double wavelength);
bool has_zone_focus(const Aperture& aperture);  // a zone plate or a photon sieve

// Parses --aperture text: circle, square, polygon:N[:ROTATIONdeg], mask:FILE, zoneplate:N,
// sieve:N[:Kx][:FILL%][:SEED].
// A mask comes back with `mask_file` set and no pixels: the image layer reads it
// (wavecam/aperture_mask.h); errors name `field`.
Result<Aperture> parse_aperture(const std::string& text, const std::string& field);

// Installs mask pixels (greyscale, row-major, row 0 at the top); refuses an all-zero or
// out-of-range image, naming `field` and the file.
Result<bool> set_aperture_mask(Aperture& aperture, int width, int height, std::vector<float> amplitude,
                               const std::string& field);

// Pinhole samples as structure-of-arrays, ready for the propagation kernels.
// Positions in metres on the plane z = 0; weight = transmission x area of the sample's cell (m^2).
struct ApertureSamples {
    std::vector<float> x, y, weight;
    double pitch = 0.0;
    size_t size() const { return x.size(); }
};

// Lattice pitch for a wavelength: lambda / 2 samples waves arriving from any angle (the seed
// paper's Nyquist argument); lambda / (2 sin theta_max) suffices when every source and film
// direction lies within theta_max of the axis.
double sample_pitch(double wavelength, double sin_theta_max = 1.0);

// Samples the aperture on a square lattice of the given pitch, cells centred on (m p, n p).
// Edge handling: a cell the rim crosses keeps one sample at the centroid of its open part,
// weighted by the open area (16x16 sub-cell estimate; exact for a sieve's holes), so the total
// weight equals the aperture's area to O(pitch^2 / diameter) and rim cells don't bias the
// Fresnel zones. The pitch is refined to resolved_pitch where it is too coarse for the
// aperture's finest opening; `pitch` in the result is the one used.
ApertureSamples sample_aperture(const Aperture& aperture, double pitch);

// At least kSamplesAcrossFinest samples across the aperture's finest opening (a sieve's
// smallest hole): min(pitch, finest_width / kSamplesAcrossFinest).
constexpr double kSamplesAcrossFinest = 4;
double resolved_pitch(const Aperture& aperture, double pitch);

// Number of samples sample_aperture would return (approximately), without allocating.
double estimate_sample_count(const Aperture& aperture, double pitch);

}  // namespace wavecam
