#include "wavecam/scene_diffraction.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "counter_random.h"
#include "wavecam/propagation.h"

namespace wavecam {
namespace {

Result<bool> validate(const MonochromeScene& scene, double wavelength, const DiffractionSettings& s) {
    auto fail = [](const std::string& m) { return Result<bool>::failure(m); };
    const PinholeCamera& c = scene.camera;
    if (!(s.aperture.diameter > 0)) return fail("pinhole: expected a diameter > 0");
    if (!(c.film_distance > 0)) return fail("film-distance: expected a distance > 0");
    if (!(c.fov_h > 0 && c.fov_h < M_PI * 0.999)) return fail("fov: expected a field of view in (0deg, 180deg)");
    if (c.width < 1 || c.height < 1) return fail("image: expected at least 1x1 pixels");
    if (!(wavelength > 0)) return fail("wavelengths: expected wavelengths > 0");
    if (s.runs < 1) return fail("runs: expected at least 1 run");
    if (!scene.power || !scene.depth) return fail("image: radiance and depth are required");
    const long n = long(c.width) * c.height;
    for (long p = 0; p < n; ++p) {
        if (!std::isfinite(scene.power[p]) || scene.power[p] < 0) {
            std::ostringstream m;
            m << "radiance: pixel (" << p % c.width << ", " << p / c.width << ") is " << scene.power[p]
              << ", expected a finite value >= 0";
            return fail(m.str());
        }
        if (std::isnan(scene.depth[p]) || !(scene.depth[p] > 0)) {
            std::ostringstream m;
            m << "depth: pixel (" << p % c.width << ", " << p / c.width << ") is " << scene.depth[p]
              << ", expected a distance > 0 (inf or >= 1e9 for sky)";
            return fail(m.str());
        }
    }
    return Result<bool>::success(true);
}

// The point source for pixel (i, j), placed at image position (x, y) within it.
// Irradiance on the pinhole = radiance x pixel solid angle whatever the depth (docs/physics.md):
// a finite source gets amplitude sqrt(L Omega) |P| so that |U|^2 = L Omega at the pinhole.
PointSource pixel_source(const MonochromeScene& scene, int i, int j, double x, double y, double phase) {
    const PinholeCamera& c = scene.camera;
    const long p = long(j) * c.width + i;
    double u, v;
    c.tangent(x, y, u, v);
    const double norm = std::sqrt(1.0 + u * u + v * v);
    const double root_power = std::sqrt(double(scene.power[p]) * c.solid_angle(i, j));
    const double depth = scene.depth[p];
    PointSource s;
    s.phase = phase;
    if (depth >= kInfiniteDepth) {
        s.at_infinity = true;
        s.x = u / norm;
        s.y = v / norm;
        s.z = 1.0 / norm;
        s.amplitude = root_power;
        return s;
    }
    // planar depth: P = Z (u, v, 1); ray depth: P = D (u, v, 1) / |(u, v, 1)|
    const double scale = scene.depth_meaning == DepthMeaning::Planar ? depth : depth / norm;
    s.x = scale * u;
    s.y = scale * v;
    s.z = scale;
    s.amplitude = root_power * scale * norm;
    return s;
}

// n x n film points per output pixel of rows [row_begin, row_end), at the centres of an n x n
// split of the pixel, stored pixel by pixel so that point p * n^2 + k belongs to the p-th pixel
// of those rows.
FilmPoints camera_film(const PinholeCamera& c, int n, int row_begin, int row_end) {
    FilmPoints film;
    film.film_distance = c.film_distance;
    for (int j = row_begin; j < row_end; ++j)
        for (int i = 0; i < c.width; ++i)
            for (int b = 0; b < n; ++b)
                for (int a = 0; a < n; ++a) {
                    double u, v;
                    c.tangent(i + (a + 0.5) / n, j + (b + 0.5) / n, u, v);
                    film.x.push_back(static_cast<float>(-c.film_distance * u));
                    film.y.push_back(static_cast<float>(-c.film_distance * v));
                }
    return film;
}

// The share of the work the settings ask for: film rows and runs, clamped to the job.
struct WorkRange {
    int row_begin, row_end, run_begin, run_end;
};
WorkRange work_range(const DiffractionSettings& s, int height) {
    WorkRange w;
    w.row_begin = std::clamp(s.row_begin, 0, height);
    w.row_end = s.row_end < 0 ? height : std::clamp(s.row_end, w.row_begin, height);
    w.run_begin = std::clamp(s.run_begin, 0, s.runs);
    w.run_end = s.run_end < 0 ? s.runs : std::clamp(s.run_end, w.run_begin, s.runs);
    return w;
}

uint64_t wavelength_stream(double wavelength) {
    uint64_t bits;
    std::memcpy(&bits, &wavelength, sizeof bits);
    return bits;
}

}  // namespace

double scene_sample_pitch(const DiffractionSettings& s, const PinholeCamera& camera, double wavelength,
                          double nearest) {
    if (s.sin_theta_max > 0) return sample_pitch(wavelength, s.sin_theta_max);
    const double sin_corner = camera.sin_max_field_angle();
    const double tan_corner = sin_corner / std::sqrt(1.0 - sin_corner * sin_corner);
    const double t = tan_corner + 0.5 * s.aperture.diameter / std::min(camera.film_distance, nearest);
    const double sin_max = t / std::sqrt(1.0 + t * t) + wavelength / s.aperture.diameter;
    // At least kMinSamplesAcross across the pinhole, so the rim is resolved as a quadrature.
    return std::min(sample_pitch(wavelength, std::min(1.0, sin_max)), s.aperture.diameter / kMinSamplesAcross);
}

int auto_film_subsamples(const Aperture& aperture, const PinholeCamera& camera, double wavelength) {
    // The film field is the pupil's transform (fresnel_psf.h), so the irradiance holds no
    // frequency above span / (lambda f): its finest fringe is lambda f / span, at any depth
    // (cos theta only widens it off axis). Film points closer than that sum every pixel's
    // fringes to their area average; one point per pixel samples them instead.
    const double span = 2 * aperture.bounding_radius();
    const double finest_fringe = wavelength * camera.film_distance / span;
    const double pixel = camera.pixel_pitch();
    return std::clamp(int(std::floor(pixel / finest_fringe)) + 1, 1, kMaxFilmSubsamples);
}

double nearest_depth(const PinholeCamera& camera, const float* depth, DepthMeaning meaning) {
    double z = INFINITY;
    for (int j = 0; j < camera.height; ++j)
        for (int i = 0; i < camera.width; ++i) {
            const double d = depth[size_t(j) * camera.width + i];
            if (d < kInfiniteDepth) z = std::min(z, camera.planar_depth(i, j, d, meaning));
        }
    return z;
}

double scene_terms(const DiffractionSettings& s, const PinholeCamera& camera, double wavelength, double nearest) {
    const double samples = estimate_sample_count(s.aperture, scene_sample_pitch(s, camera, wavelength, nearest));
    const double pixels = double(camera.width) * camera.height;
    const int sub = s.film_subsamples > 0 ? s.film_subsamples : auto_film_subsamples(s.aperture, camera, wavelength);
    const WorkRange w = work_range(s, camera.height);
    const double film = double(camera.width) * (w.row_end - w.row_begin) * sub * sub;
    return s.method == CoherenceMethod::Incoherent ? samples * pixels * (film + 1)
                                                   : samples * (pixels + film) * (w.run_end - w.run_begin);
}

Result<bool> diffract_monochrome(const MonochromeScene& scene, double wavelength, const DiffractionSettings& s,
                                 float* irradiance, const ProgressFn& progress) {
    if (auto v = validate(scene, wavelength, s); !v.ok()) return v;
    const PinholeCamera& c = scene.camera;
    const ApertureSamples samples =
        sample_aperture(s.aperture, scene_sample_pitch(s, c, wavelength, nearest_depth(c, scene.depth, scene.depth_meaning)));
    const int sub = s.film_subsamples > 0 ? s.film_subsamples : auto_film_subsamples(s.aperture, c, wavelength);
    const WorkRange range = work_range(s, c.height);
    const FilmPoints film = camera_film(c, sub, range.row_begin, range.row_end);
    // Irradiance at every film point; averaged into the output pixels after each run.
    std::vector<float> points(film.size(), 0.0f);
    auto average_into_output = [&] {
        const size_t n2 = size_t(sub) * sub;
        float* out = irradiance + size_t(range.row_begin) * c.width;
        for (size_t p = 0; p < points.size() / n2; ++p) {
            double sum = 0;
            for (size_t k = 0; k < n2; ++k) sum += points[p * n2 + k];
            out[p] += static_cast<float>(sum / n2);
        }
        std::fill(points.begin(), points.end(), 0.0f);
        return Result<bool>::success(true);
    };
    const uint64_t stream = wavelength_stream(wavelength);
    PinholeField field;
    auto cancelled = [] { return Result<bool>::failure("cancelled"); };

    if (s.method == CoherenceMethod::Incoherent) {
        const long n = long(c.width) * c.height;
        for (long p = 0; p < n; ++p) {
            if (scene.power[p] <= 0) continue;
            const int i = int(p % c.width), j = int(p / c.width);
            illuminate_pinhole(samples, {pixel_source(scene, i, j, i + 0.5, j + 0.5, 0.0)}, wavelength, field,
                               s.nthreads);
            const double done = double(p) / n;
            ProgressFn report;
            if (progress) report = [&](double f) { return progress(done + f / n); };
            if (!accumulate_film_irradiance(samples, field, film, wavelength, 1.0, points.data(), s.nthreads, report))
                return cancelled();
        }
        return average_into_output();
    }

    for (int run = range.run_begin; run < range.run_end; ++run) {
        std::vector<PointSource> sources;
        sources.reserve(size_t(c.width) * c.height);
        for (int j = 0; j < c.height; ++j)
            for (int i = 0; i < c.width; ++i) {
                const uint64_t p = uint64_t(j) * c.width + i;
                if (scene.power[p] <= 0) continue;
                const double jx = s.jitter ? detail::counter_uniform(s.seed, run, p, 1) : 0.5;
                const double jy = s.jitter ? detail::counter_uniform(s.seed, run, p, 2) : 0.5;
                const double phase = 2 * M_PI * detail::counter_uniform(s.seed ^ stream, run, p, 3);
                sources.push_back(pixel_source(scene, i, j, i + jx, j + jy, phase));
            }
        // Progress: half of a run's terms go to the pinhole, half to the film.
        auto stage = [&](double offset) -> ProgressFn {
            if (!progress) return {};
            return [&progress, offset, first = range.run_begin, runs = range.run_end - range.run_begin, run](double f) {
                return progress((run - first + offset + 0.5 * f) / runs);
            };
        };
        if (!illuminate_pinhole(samples, sources, wavelength, field, s.nthreads, stage(0.0))) return cancelled();
        if (!accumulate_film_irradiance(samples, field, film, wavelength, 1.0 / s.runs, points.data(), s.nthreads,
                                        stage(0.5)))
            return cancelled();
        average_into_output();
    }
    return Result<bool>::success(true);
}

}  // namespace wavecam
