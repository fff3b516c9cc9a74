#include "summation/kernel/source_kernels.h"

#include <cmath>

#include "summation/scene_sum.h"

namespace wavecam::detail {

UnitSource unit_sources(const PinholeCamera& c) {
    return [c](double x, double y, double w) {
        return source_at(c, {x, y, w > 0 ? 1.0 / w : INFINITY, DepthMeaning::Planar}, 1.0, 0.0);
    };
}

Result<bool> source_kernels(const KernelSetup& k, int px, int py, const std::vector<double>& inverse_depths,
                            const SummationSettings& settings, PlanScope& film_scope,
                            std::vector<std::vector<std::complex<double>>>& fields) {
    const KernelSummationSpec& spec = *k.spec;
    const KernelSummationGeometry& g = *k.g;
    const PinholeCamera& c = spec.camera;
    const int n = spec.subsamples;
    FilmPoints film;
    film.film_distance = c.film_distance;
    for (int sb = 0; sb < n; ++sb)
        for (int sa = 0; sa < n; ++sa)
            for (int dy = -g.radius; dy <= g.radius; ++dy)
                for (int dx = -g.radius; dx <= g.radius; ++dx) {
                    double u, v;
                    c.tangent(px + dx + (sa + 0.5) / n, py + dy + (sb + 0.5) / n, u, v);
                    film.x.push_back(float(-c.film_distance * u));
                    film.y.push_back(float(-c.film_distance * v));
                }
    SummationPlan to_film =
        SummationPlan::create(*k.device, SumKind::PinholeToFilm, *k.samples, spec.wavelength, settings, film_scope);
    if (auto r = to_film.set_points(film); !r.ok()) return r;
    film_scope.fixed_choice = true;  // every source's film points count alike: one decision
    film_scope.choice = to_film.choice();
    SummationSettings to_source = k.to_pinhole;
    to_source.nthreads = settings.nthreads;
    PinholeField field;
    fields.assign(inverse_depths.size(), {});
    for (size_t l = 0; l < inverse_depths.size(); ++l) {
        const std::vector<PointSource> one{k.unit(px + 0.5, py + 0.5, inverse_depths[l])};
        SummationPlan to_pinhole =
            SummationPlan::create(*k.device, SumKind::SourcesToPinhole, *k.samples, spec.wavelength, to_source);
        if (auto r = to_pinhole.set_points(one); !r.ok()) return r;
        if (auto r = to_pinhole.execute(source_weights(one), field); !r.ok()) return r;
        fields[l].assign(film.size(), 0.0);
        if (auto r = to_film.execute(field, fields[l].data()); !r.ok()) return r;
    }
    return Result<bool>::success(true);
}

}  // namespace wavecam::detail
