#include "wavecam/edge_continuation.h"
#include "summation/scene_sum.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "summation/frame_margin.h"

namespace wavecam {
namespace detail {

// The settings one wavelength's sum needs (the pixels are check_pixels').
Result<bool> check_settings(const PinholeCamera& c, double wavelength, const SceneSumSettings& s) {
    auto fail = [](const std::string& m) { return Result<bool>::failure(m); };
    if (!(s.aperture.diameter > 0)) return fail("pinhole: expected a diameter > 0");
    if (!(c.film_distance > 0)) return fail("film-distance: expected a distance > 0");
    if (!(c.fov_h > 0 && c.fov_h < M_PI * 0.999)) return fail("fov: expected a field of view in (0deg, 180deg)");
    if (!(wavelength > 0)) return fail("wavelengths: expected wavelengths > 0");
    if (s.runs < 1) return fail("runs: expected at least 1 run");
    if (s.summation == Summation::Kernel && s.jitter)
        return fail("jitter: the kernel summation places every source at its pixel's centre; expected no jitter, or "
                    "summation auto, direct or nufft");
    return check_frame(c, s.overscan);
}

// A point source at `at` with power `power_on_pinhole` = radiance x solid angle: the irradiance
// it puts on the pinhole whatever its depth (docs/physics.md), so a finite source gets amplitude
// sqrt(L Omega) |P|.
PointSource source_at(const PinholeCamera& c, const ScenePoint& at, double power_on_pinhole, double phase) {
    const double depth = at.depth;
    double u, v;
    c.tangent(at.x, at.y, u, v);
    const double norm = std::sqrt(1.0 + u * u + v * v);
    const double root_power = std::sqrt(power_on_pinhole);
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
    const double scale = at.meaning == DepthMeaning::Planar ? depth : depth / norm;
    s.x = scale * u;
    s.y = scale * v;
    s.z = scale;
    s.amplitude = root_power * scale * norm;
    return s;
}


std::vector<Emitter> scene_emitters(const MonochromeScene& scene, const std::vector<detail::MarginCell>& cells) {
    const PinholeCamera& c = scene.camera;
    std::vector<Emitter> e;
    const uint64_t pixels = uint64_t(c.width) * c.height;
    for (int j = 0; j < c.height; ++j)
        for (int i = 0; i < c.width; ++i) {
            const uint64_t p = uint64_t(j) * c.width + i;
            if (scene.power[p] <= 0) continue;
            e.push_back({double(i), double(j), 1.0, 1.0, scene.power[p] * c.solid_angle(i, j), scene.depth[p],
                         scene.depth_meaning, p});
        }
    const EdgeContinuation edge(scene.power, 1, c.width, c.height);  // a lone bright edge pixel is not copied beyond
    for (size_t k = 0; k < cells.size(); ++k) {
        const detail::MarginCell& m = cells[k];
        const size_t q = size_t(m.edge_y) * c.width + m.edge_x;
        const float power = *edge.at(m.edge_x, m.edge_y);
        if (power <= 0) continue;
        const double d = scene.depth[q];
        e.push_back({double(m.x0), double(m.y0), double(m.x1 - m.x0), double(m.y1 - m.y0),
                     power * detail::block_solid_angle(c, m.x0, m.x1, m.y0, m.y1),
                     d >= kInfiniteDepth ? d : c.planar_depth(m.edge_x, m.edge_y, d, scene.depth_meaning),
                     DepthMeaning::Planar, pixels + k});
    }
    return e;
}


// The pinhole lattice for sources within `source` and film points within `film`: the frame's
// own (scene_sample_pitch), refined where sources beyond it need it. A square lattice of pitch h
// also sends light to directions shifted by lambda / h along each axis; they miss the film while
// lambda / h >= sin(widest source) + sin(widest film point) on that axis (frame_margin.h).
double lattice_pitch(const SceneSumSettings& s, const PinholeCamera& c, double wavelength, double nearest,
                     const Extent& source, const Extent& film) {
    const double frame = scene_sample_pitch(s, c, wavelength, nearest);
    if (s.sin_theta_max > 0) return frame;
    const double widen = 0.5 * s.aperture.diameter / std::min(c.film_distance, nearest);
    auto sine = [&](double t) {
        return std::min(1.0, (t + widen) / std::sqrt(1.0 + (t + widen) * (t + widen)) + wavelength / s.aperture.diameter);
    };
    const double need = std::max(sine(source.u) + sine(film.u), sine(source.v) + sine(film.v));
    return std::min(frame, wavelength / need);
}

// n x n film points per output pixel of rows [row_begin, row_end) and columns [col_begin,
// col_end), at the centres of an n x n split of the pixel, stored pixel by pixel so that point
// p * n^2 + k belongs to the p-th pixel of that window.
FilmPoints camera_film(const PinholeCamera& c, int n, int row_begin, int row_end, int col_begin, int col_end) {
    FilmPoints film;
    film.film_distance = c.film_distance;
    for (int j = row_begin; j < row_end; ++j)
        for (int i = col_begin; i < col_end; ++i)
            for (int b = 0; b < n; ++b)
                for (int a = 0; a < n; ++a) {
                    double u, v;
                    c.tangent(i + (a + 0.5) / n, j + (b + 0.5) / n, u, v);
                    film.x.push_back(static_cast<float>(-c.film_distance * u));
                    film.y.push_back(static_cast<float>(-c.film_distance * v));
                }
    return film;
}

WorkRange work_range(const SceneSumSettings& s, int height) {
    const int o = std::clamp(s.overscan, 0, height / 2);
    WorkRange w;
    w.row_begin = std::clamp(s.row_begin, o, height - o);
    w.row_end = s.row_end < 0 ? height - o : std::clamp(s.row_end, w.row_begin, height - o);
    w.run_begin = std::clamp(s.run_begin, 0, s.runs);
    w.run_end = s.run_end < 0 ? s.runs : std::clamp(s.run_end, w.run_begin, s.runs);
    return w;
}

uint64_t wavelength_stream(double wavelength) {
    uint64_t bits;
    std::memcpy(&bits, &wavelength, sizeof bits);
    return bits;
}

// Film points per pixel side: as asked, or auto_film_subsamples.
int film_subsamples(const SceneSumSettings& s, const PinholeCamera& camera, double wavelength) {
    return s.film_subsamples > 0 ? s.film_subsamples : auto_film_subsamples(s.aperture, camera, wavelength);
}


// With `scene.power` null every pixel and margin cell counts as lit (estimates).
SceneSum scene_sum(const MonochromeScene& scene, double wavelength, const SceneSumSettings& s, double nearest,
                   const WorkRange& range, bool with_samples) {
    const PinholeCamera& c = scene.camera;
    const int o = std::clamp(s.overscan, 0, std::min(c.width, c.height) / 2);
    SceneSum sum;
    Extent film, frame;
    film.add(c, o, o, c.width - o, c.height - o);
    frame.add(c, 0, 0, c.width, c.height);
    // The margin's reach: as far as the frame's own lattice carries, within the radii (frame_margin.h).
    const detail::MarginRadii radii = detail::margin_radii(s.aperture, c, o, nearest, wavelength);
    const double frame_pitch = lattice_pitch(s, c, wavelength, nearest, frame, film);
    const int least = std::min(radii.reach, detail::kMinReachRadii * radii.kernel);
    int reach = radii.reach;
    for (;;) {
        Extent margin = frame;
        margin.add(c, o - reach, o - reach, c.width - o + reach, c.height - o + reach);
        if (reach <= least || lattice_pitch(s, c, wavelength, nearest, margin, film) >= frame_pitch) break;
        reach = std::max(least, reach - std::max(1, radii.kernel / 2));
    }
    const std::vector<detail::MarginCell> cells = detail::margin_cells(c, o, reach, radii.rho);
    Extent source = frame;
    if (scene.power) {
        sum.emitters = scene_emitters(scene, cells);
        for (const Emitter& e : sum.emitters) source.add(c, e.x, e.y, e.x + e.w, e.y + e.h);
        sum.emitter_count = sum.emitters.size();
    } else {
        source.add(c, o - reach, o - reach, c.width - o + reach, c.height - o + reach);
        sum.emitter_count = size_t(c.width) * c.height + cells.size();
    }
    const double pitch = lattice_pitch(s, c, wavelength, nearest, source, film);
    sum.source_extent = source;
    sum.film_extent = film;
    if (with_samples) sum.samples = sample_aperture(s.aperture, pitch);
    else sum.samples.pitch = pitch;
    sum.subsamples = film_subsamples(s, c, wavelength);
    if (with_samples) sum.film = camera_film(c, sum.subsamples, range.row_begin, range.row_end, o, c.width - o);
    return sum;
}

}  // namespace detail
}  // namespace wavecam
