#include "psf_measures.h"

#include <cmath>

namespace wavecam::test {
namespace {
// Distance of pixel (i, j) from the window centre, in metres.
double pixel_radius(const PsfImage& img, int i, int j) {
    const double c = 0.5 * (img.resolution - 1);
    return std::hypot(i - c, j - c) * img.pixel_pitch;
}
}  // namespace

double encircled_energy(const PsfImage& img, double radius) {
    const int n = img.resolution;
    double sum = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
            if (radius < 0 || pixel_radius(img, i, j) <= radius) sum += img.irradiance[size_t(j) * n + i];
    return sum * img.pixel_pitch * img.pixel_pitch;
}

void centroid_offset(const PsfImage& img, double& dx, double& dy) {
    const int n = img.resolution;
    const double c = 0.5 * (n - 1);
    double s = 0, sx = 0, sy = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double v = img.irradiance[size_t(j) * n + i];
            s += v;
            sx += v * -(i - c) * img.pixel_pitch;  // image column i is film -x
            sy += v * (j - c) * img.pixel_pitch;   // image row j is film +y
        }
    dx = sx / s;
    dy = sy / s;
}

std::vector<double> azimuthal_profile(const PsfImage& img, double bin) {
    const int n = img.resolution;
    const size_t bins = static_cast<size_t>(n * img.pixel_pitch / (2 * bin)) + 1;
    std::vector<double> sum(bins, 0.0), count(bins, 0.0);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const size_t b = static_cast<size_t>(pixel_radius(img, i, j) / bin);
            if (b >= bins) continue;
            sum[b] += img.irradiance[size_t(j) * n + i];
            count[b] += 1;
        }
    for (size_t b = 0; b < bins; ++b) sum[b] = count[b] > 0 ? sum[b] / count[b] : 0.0;
    return sum;
}

double mean_in_annulus(const PsfImage& img, double r0, double r1) {
    const int n = img.resolution;
    double s = 0, count = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double r = pixel_radius(img, i, j);
            if (r >= r0 && r < r1) {
                s += img.irradiance[size_t(j) * n + i];
                count += 1;
            }
        }
    return s / count;
}

}  // namespace wavecam::test
