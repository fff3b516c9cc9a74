// The seed paper's "Diffraction of a point source": point-source images over a range of
// pinhole diameters and the spot size against diameter, whose minimum is the optimal pinhole.
#pragma once
#include <vector>
#include "wavecam/psf.h"

namespace wavecam {

struct SweepParams {
    double film_distance = 50e-3;
    double wavelength = 550e-9;
    double min_scale = 0.4, max_scale = 4.0;  // diameters from min to max x sqrt(f lambda)
    int count = 13;                           // log-spaced diameters
    int resolution = 101;                     // pixels across each PSF window
    int nthreads = 0;
    // Shape swept (its diameter is replaced by each point's): for a non-circular aperture the
    // diameter is its size parameter (side, circumscribed diameter, mask width, outer diameter)
    // and r50/r80 are still radii of centred circles holding that share of the light.
    Aperture aperture;
};

struct SweepPoint {
    double diameter = 0;
    double r50 = 0, r80 = 0;  // encircled-energy radii (m): 50% and 80% of the light through the pinhole
    PsfImage psf;             // window 3 x max(shadow, Airy diameter) wide
};

// Exact PSFs (a source at infinity on axis) for each diameter; encircled energy is measured
// against the total the pinhole passes, pi a^2 in relative-irradiance units (energy result).
Result<std::vector<SweepPoint>> sweep_pinholes(const SweepParams& p, const ProgressFn& progress = {});

// The diameter of the smallest spot, refined by a parabola through the three points around the
// minimum of r50 in log d.
double optimal_diameter(const std::vector<SweepPoint>& points);

}  // namespace wavecam
