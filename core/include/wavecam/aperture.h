// The pinhole: an opening in the plane z = 0 centred on the origin, and its sampling.
#pragma once
#include <cstddef>
#include <string>
#include <vector>
#include "wavecam/result.h"

namespace wavecam {

enum class ApertureShape { Circle, Square };

struct Aperture {
    ApertureShape shape = ApertureShape::Circle;
    double diameter = 0.0;  // metres; the side for a square

    // Fraction of the axis-aligned cell [x0,x1]x[y0,y1] that is open, and the open part's centroid.
    double coverage(double x0, double x1, double y0, double y1, double& cx, double& cy) const;
    double area() const;
    bool contains(double x, double y) const;
};

Result<ApertureShape> parse_aperture_shape(const std::string& name, const std::string& field);

// Pinhole samples as structure-of-arrays, ready for the propagation kernels.
// Positions in metres on the plane z = 0; weight = open area of the sample's cell (m^2).
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
// weighted by the open area (16x16 sub-cell estimate), so the total weight equals the
// aperture's area to O(pitch^2 / diameter) and rim cells don't bias the Fresnel zones.
ApertureSamples sample_aperture(const Aperture& aperture, double pitch);

// Number of samples sample_aperture would return (approximately), without allocating.
double estimate_sample_count(const Aperture& aperture, double pitch);

}  // namespace wavecam
