// One source model for all three methods (docs/physics.md, "What a pixel is"): a rendered pixel
// is a point source at its centre, and each film pixel's irradiance is averaged over its area.
// So the convolution method, the incoherent sum and the random-phase runs' limit must give one
// image: on a textured frame at a PSF of two pixels, where the model's choices show most, each
// pair within 1.5% RMS per channel, at 10 deg on 32 px and at 60 deg on 24 px (the same field on
// fewer pixels, the PSF as wide in pixels: the exact incoherent sum there took 97 s on 32 px).
// Measured: 0.02-0.7% at 10 deg; 0.2-0.74% at 60 deg (0.2-1.0% on 32 px), where the convolution
// method's level sits 0.1-0.7% off the point sums' (a uniform wall, docs/physics.md). At 60 deg the incoherent reference is summed exactly (nufft), not by the
// kernel summation, whose own error there (up to its 1.5%) would add to the models' differences.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "wavecam/diffract_image.h"

using namespace wavecam;

namespace {

// side x side random grey radiance (0.1 .. 1) at 2 m over `fov` degrees.
OIIO::ImageBuf textured_frame(int side, float fov) {
    OIIO::ImageSpec spec(side, side, 4, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "Z"};
    spec.attribute("wavecam.fov", fov);
    OIIO::ImageBuf buf(spec);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.1f, 1.0f);
    for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) {
            const float v = u(rng), px[4] = {v, v, v, 2.0f};
            buf.setpixel(i, j, px);
        }
    return buf;
}

std::vector<float> diffracted(const OIIO::ImageBuf& src, DiffractMethod method, double pinhole, int runs,
                              Summation summation) {
    DiffractOptions opt;
    opt.method = method;
    opt.pinhole = pinhole;
    opt.wavelength_count = 3;
    opt.scene_sum.runs = runs;
    opt.scene_sum.summation = summation;
    OIIO::ImageBuf dst;
    EXPECT_TRUE(diffract(dst, src, "textured", opt)) << dst.geterror();
    const int w = src.spec().width;
    std::vector<float> rgb(3 * size_t(w) * w);
    dst.get_pixels(OIIO::ROI(0, w, 0, w, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, rgb.data());
    return rgb;
}

// RMS over the pixels `border` or more from the edges of a / b - 1, channel c.
double rms_ratio(const std::vector<float>& a, const std::vector<float>& b, int side, int border, int c) {
    double sum = 0;
    int n = 0;
    for (int j = border; j < side - border; ++j)
        for (int i = border; i < side - border; ++i) {
            const size_t p = 3 * (size_t(j) * side + i) + c;
            sum += std::pow(double(a[p]) / b[p] - 1, 2);
            ++n;
        }
    return std::sqrt(sum / n);
}

}  // namespace

TEST(OneSourceModel, AllThreeMethodsConvergeToOneImage) {
    for (const float fov : {10.0f, 60.0f}) {
        // 32 pixels, 24 at 60 deg: the exact incoherent sum's terms grow as the side's fourth power
        const int side = fov > 30 ? 24 : 32;
        // the Airy radius two pixels on the axis at 550 nm
        const double pitch = 50e-3 * 2 * std::tan(0.5 * fov * M_PI / 180) / side;
        const double pinhole = 1.22 * 550e-9 * 50e-3 / (2 * pitch);
        const OIIO::ImageBuf src = textured_frame(side, fov);
        const auto convolution = diffracted(src, DiffractMethod::Convolution, pinhole, 1, Summation::Auto);
        // the reference: at 60 deg, where `auto` would take the kernel summation, the point sums (the
        // NUFFTs, 3e-4) by name; at 10 deg `auto` (the kernel summation, as for the runs: that pair then differs by
        // the runs' noise alone; the kernel summation against the point sums has its own tests)
        const auto incoherent = diffracted(src, DiffractMethod::Incoherent, pinhole, 1,
                                           fov > 30 ? Summation::Nufft : Summation::Auto);
        // (1024 coded runs: the PSF spans about 30 pixels at the longest wavelength, so the runs'
        // noise is a few tenths of a percent)
        const auto random_phase = diffracted(src, DiffractMethod::RandomPhase, pinhole, 1024, Summation::Auto);
        for (int c = 0; c < 3; ++c) {
            const double ci = rms_ratio(convolution, incoherent, side, 6, c);
            const double ri = rms_ratio(random_phase, incoherent, side, 6, c);
            const double cr = rms_ratio(convolution, random_phase, side, 6, c);
            std::printf("%g deg, channel %c: convolution / incoherent %.2f%%, random-phase / incoherent %.2f%%, "
                        "convolution / random-phase %.2f%% RMS\n",
                        fov, "RGB"[c], 100 * ci, 100 * ri, 100 * cr);
            EXPECT_LE(ci, 0.015) << fov << " deg, " << "RGB"[c];
            EXPECT_LE(ri, 0.015) << fov << " deg, " << "RGB"[c];
            EXPECT_LE(cr, 0.015) << fov << " deg, " << "RGB"[c];
        }
    }
}
