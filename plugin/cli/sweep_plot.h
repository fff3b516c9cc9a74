// The pictures of `wavecam sweep`: the PSFs as a contact sheet with scale bars in micrometres,
// and spot size against pinhole diameter on log axes with ticks, units, a legend and the
// optimum marked with its value.
#pragma once
#include <OpenImageIO/imagebuf.h>

#include <string>
#include <vector>

#include "wavecam/pinhole_sweep.h"

namespace wavecam::cli {

// What the pictures say besides the points: the camera and the three optima (metres).
struct SweepFigure {
    double film_distance = 0, wavelength = 0;
    std::string aperture;
    double rayleigh = 0, paper = 0, best = 0;  // 1.9 sqrt(f lambda), sqrt(D lambda / 2) at D = 5f, least r50
};

OIIO::ImageBuf psf_sheet(const std::vector<SweepPoint>& points, const SweepFigure& figure);
OIIO::ImageBuf spot_size_plot(const std::vector<SweepPoint>& points, const SweepFigure& figure);

// r50 at diameter d: the parabola in log d through the three points nearest d (the one
// `optimal_diameter` puts its vertex on), or the nearest point's r50 at the ends.
double r50_at(const std::vector<SweepPoint>& points, double d);

}  // namespace wavecam::cli
