// The midpoint rule's error for a pixel's average, weighted by the OTF (pixel_average.h).
#include "summation/pixel_average.h"

#include <algorithm>
#include <cmath>

namespace wavecam::detail {

double pixel_average_error(int n, double pfc) {
    if (pfc <= 0) return 0;
    constexpr int kSteps = 400;
    double worst = 0;
    for (int i = 1; i <= kSteps; ++i) {
        const double x = pfc * i / kSteps, nu = double(i) / kSteps;
        const double box = std::sin(M_PI * x) / (M_PI * x);
        const double s = std::sin(M_PI * x / n);
        const double points = std::fabs(s) < 1e-12 ? 1.0 : std::sin(M_PI * x) / (n * s);
        const double otf = 2 / M_PI * (std::acos(nu) - nu * std::sqrt(std::max(0.0, 1 - nu * nu)));
        worst = std::max(worst, std::fabs(box - points) * otf);
    }
    return worst;
}

}  // namespace wavecam::detail
