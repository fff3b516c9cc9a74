// One lit pixel (a star) at depth z in a tiny square render, through the random-phase method's
// point sums with one run, no jitter and one film point per pixel; and the image the point-source
// computation (compute_psf) says each wavelength must give it. Shared by the scene and the
// monochrome tests, which light the star in colour and in grey.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "wavecam/psf.h"
#include "wavecam/scene_diffraction.h"
#include "wavecam/spectral_diffraction.h"
#include "summation_flag.h"

namespace wavecam::test {

// XYZ -> linear Rec.709 (IEC 61966-2-1); any invertible matrix serves a spectral basis.
const Matrix3 kXyzTo709{{{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}}};

// A w x w camera whose film pixels are `film_pixel` wide at film distance f.
inline PinholeCamera small_camera(int w, double f, double film_pixel) {
    return {w, w, 2 * std::atan(w * film_pixel / (2 * f)), f};
}

struct OneStarScene {
    static constexpr double f = 20e-3, z = 0.3;
    static constexpr int w = 9, i0 = 5, j0 = 4;  // the star, on the middle row (v = 0)
    PinholeCamera camera = small_camera(w, f, 5e-6);
    SceneSumSettings settings = [] {
        SceneSumSettings s;
        s.summation = test_summation();
        s.aperture = {ApertureShape::Circle, 0.2e-3};
        s.jitter = false;
        s.runs = 1;
        s.film_subsamples = 1;
        return s;
    }();

    // The film's XYZ when the star has radiance `rgb` and the rest is black.
    std::vector<float> diffract(const SpectralBasis& basis, const float rgb[3]) const {
        std::vector<float> radiance(3 * w * w, 0.0f), depth(w * w, float(z)), xyz(3 * w * w);
        for (int k = 0; k < 3; ++k) radiance[3 * (j0 * w + i0) + k] = rgb[k];
        const auto r = diffract_spectral({camera, radiance.data(), depth.data(), DepthMeaning::Planar}, basis,
                                         settings.aperture, wave_propagator(settings, test_device()), {true, xyz.data()});
        EXPECT_TRUE(r.ok()) << r.error;
        return xyz;
    }

    // Whether film column i lies in the point-source image's window (w wide, centred on the star).
    static bool in_window(int i) { return i - i0 + w / 2 >= 0 && i - i0 + w / 2 < w; }

    // Film irradiance per unit spectral power of the star at `wavelength`, row-major, from
    // compute_psf's relative irradiance: the star's L Omega |P|^2 / |P - C|^2, the camera's
    // exposure and the film's cos(incidence). 0 outside the window.
    std::vector<double> expected(double wavelength) const {
        double u, v;
        camera.tangent(i0 + 0.5, j0 + 0.5, u, v);
        PsfParams p;
        p.summation = test_summation();
        p.aperture = settings.aperture;
        p.film_distance = f;
        p.source_distance = z * std::sqrt(1 + u * u + v * v);
        p.source_angle = std::atan(u);  // v = 0
        p.wavelength = wavelength;
        p.resolution = w;
        p.film_size = w * camera.pixel_pitch();
        p.sin_theta_max = wavelength / (2 * scene_sample_pitch(settings, camera, wavelength, z));
        const PsfImage psf = compute_psf(p, test_device()).value;
        const double px = z * u, r2 = px * px + (z + f) * (z + f);
        const double unit =
            camera.solid_angle(i0, j0) * z * z * (1 + u * u) / r2 * exposure_scale(settings.aperture, f);
        std::vector<double> e(w * w, 0.0);
        for (int j = 0; j < w; ++j)
            for (int i = 0; i < w; ++i)
                if (in_window(i))
                    e[j * w + i] = unit * psf.irradiance[j * w + i - i0 + w / 2] * camera.cos_incidence(i, j);
        return e;
    }
};

}  // namespace wavecam::test
