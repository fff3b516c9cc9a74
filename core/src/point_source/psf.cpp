#include "wavecam/psf.h"

#include <chrono>
#include <cmath>
#include <sstream>

#include "wavecam/pinhole_design.h"
#include "wavecam/summation_plan.h"
#include "wavecam/source.h"

namespace wavecam {

Result<bool> validate(const PsfParams& p) {
    auto fail = [](const std::string& m) { return Result<bool>::failure(m); };
    if (!(p.aperture.diameter > 0)) return fail("pinhole: expected a diameter > 0");
    if (!(p.film_distance > 0)) return fail("film-distance: expected a distance > 0");
    if (!(p.source_distance > 0)) return fail("source-distance: expected a distance > 0 or 'inf'");
    if (!(std::fabs(p.source_angle) < M_PI / 2 * 0.999))
        return fail("source-angle: expected a field angle between -89.9deg and 89.9deg");
    if (!(p.wavelength > 0)) return fail("wavelength: expected a wavelength > 0");
    if (!(p.film_size > 0)) return fail("film-size: expected a width > 0");
    if (p.resolution < 1 || p.resolution > 16384) return fail("resolution: expected 1 to 16384 pixels");
    if (!(p.sin_theta_max > 0 && p.sin_theta_max <= 1))
        return fail("max-angle: expected an angle in (0deg, 90deg]");
    const double terms = psf_terms(p);
    if (terms > p.max_terms) {
        std::ostringstream m;
        m << "pinhole: " << estimate_sample_count(p.aperture, sample_pitch(p.wavelength, p.sin_theta_max))
          << " pinhole samples x " << double(p.resolution) * p.resolution << " film points = " << terms
          << " terms exceeds --max-terms " << p.max_terms
          << " (hours of work); use a smaller pinhole or resolution, --max-angle, or raise --max-terms";
        return fail(m.str());
    }
    return Result<bool>::success(true);
}

double psf_terms(const PsfParams& p) {
    return estimate_sample_count(p.aperture, sample_pitch(p.wavelength, p.sin_theta_max)) *
           double(p.resolution) * p.resolution;
}

Result<PsfImage> compute_psf(const PsfParams& p, const ComputeDevice& device, const ProgressFn& progress) {
    const auto start = std::chrono::steady_clock::now();
    if (auto v = validate(p); !v.ok()) return Result<PsfImage>::failure(v.error);

    const ApertureSamples samples = sample_aperture(p.aperture, sample_pitch(p.wavelength, p.sin_theta_max));
    const PointSource source = source_at_field_angle(p.source_distance, p.source_angle);

    PsfImage img;
    img.resolution = p.resolution;
    img.pixel_pitch = p.film_size / p.resolution;
    geometric_image_point(source, p.film_distance, img.centre_x, img.centre_y);
    img.sample_count = samples.size();
    img.sample_pitch = samples.pitch;
    img.fresnel_number =
        fresnel_number(p.aperture.diameter / 2, p.film_distance, p.source_distance, p.wavelength);

    const SummationSettings sum{p.summation, kSummationTolerance, p.nthreads};
    SummationPlan to_pinhole = SummationPlan::create(device, SumKind::SourcesToPinhole, samples, p.wavelength, sum);
    PinholeField field;
    if (auto r = to_pinhole.set_points({source}); !r.ok()) return Result<PsfImage>::failure(r);
    if (auto r = to_pinhole.execute(source_weights({source}), field); !r.ok()) return Result<PsfImage>::failure(r);

    const int n = p.resolution;
    FilmPoints film;
    film.film_distance = p.film_distance;
    film.x.resize(size_t(n) * n);
    film.y.resize(size_t(n) * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double x, y;
            film_position(img, i, j, x, y);
            film.x[size_t(j) * n + i] = static_cast<float>(x);
            film.y[size_t(j) * n + i] = static_cast<float>(y);
        }
    img.irradiance.assign(film.size(), 0.0f);
    const double scale = 1.0 / free_irradiance_at_film_centre(source, p.film_distance);
    SummationPlan to_film = SummationPlan::create(device, SumKind::PinholeToFilm, samples, p.wavelength, sum);
    if (auto r = to_film.set_points(film); !r.ok()) return Result<PsfImage>::failure(r);
    if (auto r = to_film.execute_irradiance(field, scale, img.irradiance.data(), progress); !r.ok())
        return Result<PsfImage>::failure(r);
    for (float v : img.irradiance) img.peak = std::max(img.peak, double(v));
    img.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return Result<PsfImage>::success(std::move(img));
}

}  // namespace wavecam
