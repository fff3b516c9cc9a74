#include "wavecam/convolution_method.h"


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "base/parallel.h"
#include "convolution/anchored_convolution.h"
#include "convolution/direction_convolution.h"
#include "convolution/far_tail.h"
#include "fft/column_fft.h"  // fft_friendly_size
#include "wavecam/edge_continuation.h"
#include "wavecam/fresnel_psf.h"

namespace wavecam {

// One of two evaluations of the same convolution: over field anchors on the film
// (anchored_convolution.h), or, for a pinhole in the Fraunhofer regime where it costs less, as
// one shift-invariant convolution in direction cosines (direction_convolution.h).
struct ConvolutionPlan::Impl {
    ConvolutionPlanSpec spec;
    // the geometry the plan was made for: the source domain (its pixel (0, 0) is camera pixel
    // (-origin, -origin), its margin `radius` pixels beyond the output frame), tiles and layers
    detail::KernelTableSpec geometry;
    std::optional<detail::AnchoredConvolution> anchored;
    std::optional<detail::DirectionConvolution> directions;
    // the anchored kernels' table, or the direction kernels' one-cell table: the far tail's deficits
    const detail::KernelTable& tail_table() const { return anchored ? anchored->table() : directions->tail_table(); }
};

namespace {

bool same_camera(const PinholeCamera& a, const PinholeCamera& b) {
    return a.width == b.width && a.height == b.height && a.fov_h == b.fov_h && a.film_distance == b.film_distance;
}

bool same_basis(const SpectralBasis& a, const SpectralBasis& b) {
    if (a.size() != b.size()) return false;
    for (int s = 0; s < a.size(); ++s) {
        if (a.wavelength(s) != b.wavelength(s)) return false;
        for (int p = 0; p < 3; ++p)
            if (a.power(s, p == 0, p == 1, p == 2) != b.power(s, p == 0, p == 1, p == 2) ||
                a.xyz_per_power(s)[p] != b.xyz_per_power(s)[p])
                return false;
    }
    return true;
}

// Tile side: the one asked for, at least the kernel radius (the overlap-add passes then take
// every third tile, pass_period); or large enough that the FFT's padding (2 R) costs less than
// the tile itself; never more than the whole source domain (one tile is then a whole-frame FFT).
int tile_side(int requested, int radius, int domain) {
    const int base = requested > 0 ? std::max(requested, radius) : std::max(128, 4 * radius);
    const int tile = detail::fft_friendly_size(base + 2 * radius) - 2 * radius;
    return std::min(tile, domain);
}

// Transform work (points x log2 points) per depth layer of a plan tiled as `t` says: 9 kernel
// spectra per computed anchor, and per tile 3 forward transforms for each anchor it meets and 3
// inverse; where all layers' spectra exceed what a plan keeps, 9 more per anchor a tile meets.
double transform_work(const detail::KernelTableSpec& t) {
    const double nx = detail::convolution_fft_length(t.tile, t.radius, t.domain_width),
                 ny = detail::convolution_fft_length(t.tile, t.radius, t.domain_height);
    const detail::AnchorAxis ax = detail::anchor_axis(t, false), ay = detail::anchor_axis(t, true);
    const std::vector<int> ex = detail::tile_edges(ax, t.domain_width, t.tile, t.radius, t.tiles_on_cells),
                           ey = detail::tile_edges(ay, t.domain_height, t.tile, t.radius, t.tiles_on_cells);
    auto met = [&](const detail::AnchorAxis& a, const std::vector<int>& e) {  // knots met, summed over a row of tiles
        double sum = 0;
        for (size_t k = 0; k + 1 < e.size(); ++k) sum += a.cell_of(e[k + 1] - 1) - a.cell_of(e[k]) + 2;
        return sum;
    };
    const double tiles = double(ex.size() - 1) * (ey.size() - 1);
    const double anchors = detail::computed_anchors(t, ax, ay);  // the others' spectra are theirs mirrored
    const double points = nx * ny;
    // kernels beyond the spectra a plan keeps are transformed by each tile that meets them
    // (a single tile transforms each computed anchor's once, as a plan does)
    const bool kept = tiles == 1 || detail::keeps_kernel_spectra(t.layers.count * 9 * anchors, points / 2, tiles);
    return ((kept ? 9 * anchors : 0) + (kept ? 3 : 12) * met(ax, ex) * met(ay, ey) + 3 * tiles) * points *
           std::log2(points);
}

}  // namespace

ConvolutionPlan::ConvolutionPlan(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ConvolutionPlan::~ConvolutionPlan() = default;
int ConvolutionPlan::kernel_radius() const { return impl_->geometry.radius; }
bool ConvolutionPlan::in_directions() const { return impl_->directions.has_value(); }

namespace {

// The plan's geometry: kernel radius, source domain, tiles, anchors and depth layers; and the
// evaluation: `cell` > 0 where it is the convolution in direction cosines, on cells of that many
// axis pixels.
struct PlanGeometry {
    detail::KernelTableSpec t;
    double cell = 0;
};

// Transform work of the convolution in direction cosines: three forward transforms, nine of
// kernels and three back, of the grid's size.
double direction_work(const detail::KernelTableSpec& t, double cell) {
    const detail::DirectionGrid g = detail::DirectionGrid::covering(t, cell);
    const double points = double(g.fft_width) * g.fft_height;
    return 15 * points * std::log2(points);
}

Result<PlanGeometry> plan_geometry(const ConvolutionPlanSpec& spec) {
    using R = Result<PlanGeometry>;
    const PinholeCamera& c = spec.camera;
    const int o = spec.overscan;
    if (auto v = check_frame(c, o); !v.ok()) return R::failure(v);
    // (the fronts refuse sources nearer than 10 pinhole diameters first, diffract_image.cpp; this
    // keeps the layer count's arithmetic finite for any caller: a subnormal depth overflowed it)
    if (!(spec.max_inverse_depth >= 0 && spec.max_inverse_depth <= 1e6)) {
        char m[96];
        std::snprintf(m, sizeof m, "depth: the nearest source is at %g m, expected 1 um or more",
                      1.0 / spec.max_inverse_depth);
        return R::failure(m);
    }
    const double lambda_min = spec.basis.shortest_wavelength(), lambda_max = spec.basis.longest_wavelength();
    const int out_w = c.width - 2 * o, out_h = c.height - 2 * o;
    const double pitch = c.pixel_pitch();
    const double nearest = spec.max_inverse_depth > 0 ? 1.0 / spec.max_inverse_depth : INFINITY;
    // The kernel radius is the widest PSF's at the output frame's corners: the anchors lie within
    // the frame, and sources in the margin beyond take the edge anchors' kernels (kernel_table.h).
    const WidestPsf widest{spec.aperture, c.film_distance, nearest, lambda_max,
                           c.cos_widest(o, o, o + out_w, o + out_h)};
    const int radius = psf_kernel_radius(widest, pitch, spec.settings.max_radius);
    detail::KernelTableSpec t;
    t.camera = c;
    t.origin = radius - o;
    t.domain_width = out_w + 2 * radius;
    t.domain_height = out_h + 2 * radius;
    t.tile = tile_side(spec.settings.tile, radius, std::max(t.domain_width, t.domain_height));
    t.anchor_cells = std::max(1, spec.settings.anchor_cells);
    t.radius = radius;
    t.aperture = spec.aperture;
    t.basis = &spec.basis;
    t.layers = detail::DepthLayers::spanning(spec.max_inverse_depth, spec.aperture.bounding_radius(), lambda_min,
                                             c.film_distance, pitch);
    if (spec.settings.tile <= 0) {
        // The cheapest of: even tiles; tiles of one, two or three whole anchor cells, or of a
        // half or a third of one (fewer knots met, a transform sized for them); one whole-domain
        // tile, whose transform is only the domain's side (no 2 R of padding), cheaper than
        // tiles where the kernels are large against the frame. The anchors are the same for any
        // tiling.
        std::vector<detail::KernelTableSpec> options{t};
        detail::KernelTableSpec whole = t;
        whole.tile = std::max(t.domain_width, t.domain_height);
        options.push_back(whole);
        const std::vector<int> ex = detail::cell_edges(detail::anchor_axis(t, false), t.domain_width),
                               ey = detail::cell_edges(detail::anchor_axis(t, true), t.domain_height);
        auto widest = [&](int cells) {  // the widest run of `cells` neighbouring cells
            int w = 0;
            for (const std::vector<int>* e : {&ex, &ey})
                for (size_t k = 0; k + 1 < e->size(); ++k)
                    w = std::max(w, (*e)[std::min(k + cells, e->size() - 1)] - (*e)[k]);
            return w;
        };
        // (the inner cells, narrower than the edge cells that hold the margins: tiles of one
        // inner cell, the edge cells split, meet 2 x 2 knots a layer)
        int inner = whole.tile;
        for (const std::vector<int>* e : {&ex, &ey})
            for (size_t k = 1; k + 2 < e->size(); ++k) inner = std::min(inner, (*e)[k + 1] - (*e)[k]);
        for (const int tile :
             {widest(1), widest(2), widest(3), (widest(1) + 1) / 2, (widest(1) + 2) / 3, inner}) {
            detail::KernelTableSpec cells = t;
            cells.tiles_on_cells = true;
            cells.tile = tile;
            if (tile >= radius && tile < whole.tile) options.push_back(cells);
        }
        double least = transform_work(t);
        for (const detail::KernelTableSpec& o : options)
            if (const double work = transform_work(o); work < least) {
                least = work;
                t = o;
            }
    }
    t.nthreads = detail::thread_count(spec.settings.nthreads);
    // In the Fraunhofer regime the same convolution in direction cosines, where it costs less
    // (a small pinhole's wide kernels: a whole-domain tile meeting every anchor)
    PlanGeometry g{t, 0.0};
    if (spec.settings.tile <= 0)
        if (const double cell = detail::fraunhofer_cell(t, spec.max_inverse_depth);
            cell > 0 && direction_work(t, cell) < transform_work(t))
            g.cell = cell;
    return R::success(g);
}

}  // namespace

int ConvolutionPlan::kernel_radius(const ConvolutionPlanSpec& spec) {
    auto g = plan_geometry(spec);
    return g.ok() ? g.value.t.radius : 0;
}

double ConvolutionPlan::estimate_bytes(const ConvolutionPlanSpec& spec) {
    auto g = plan_geometry(spec);
    if (!g.ok()) return 0;
    const detail::KernelTableSpec& t = g.value.t;
    if (g.value.cell > 0) return detail::DirectionConvolution::estimate_bytes(t, g.value.cell);
    const detail::AnchorAxis ax = detail::anchor_axis(t, false), ay = detail::anchor_axis(t, true);
    const double side = 2.0 * t.radius + 1, nx = detail::convolution_fft_length(t.tile, t.radius, t.domain_width),
                 ny = detail::convolution_fft_length(t.tile, t.radius, t.domain_height);
    const double spectrum = nx * std::floor(ny / 2 + 1) * 8;  // bytes of one (real_fft2d.h)
    const double spectra = t.layers.count * detail::computed_anchors(t, ax, ay) * 9 * spectrum;
    const double tile_count = double(detail::tile_edges(ax, t.domain_width, t.tile, t.radius, t.tiles_on_cells).size() - 1) *
                              (detail::tile_edges(ay, t.domain_height, t.tile, t.radius, t.tiles_on_cells).size() - 1);
    const bool kept = detail::keeps_kernel_spectra(spectra / spectrum, spectrum / 8, tile_count);
    // the kernels, and their spectra where kept (the kernels themselves then freed)
    const double kernels = t.layers.count * detail::computed_anchors(t, ax, ay) * 9 * side * side * sizeof(float);
    const double domain = double(t.domain_width) * t.domain_height * 5;  // layer, share
    // each thread's tile arrays, or one set that the threads share (anchored_convolution.h; a
    // group's anchors at most four)
    const double tile_pixels = std::min<double>(t.tile, t.domain_width) * std::min<double>(t.tile, t.domain_height);
    const double set = detail::tile_scratch_bytes(nx * ny, tile_pixels, spectrum / 8, kept ? 1 : 4, !kept);
    const double tiles =
        (detail::shares_tile_scratch(tile_count, t.nthreads, set, spec.settings.tile_memory) ? 1 : t.nthreads) * set;
    // each thread's working memory for one PSF of the table, at its largest: the nearest layer
    // or the sky, on the axis or at the corner anchor, the shortest or the longest wavelength
    const double lambda_min = spec.basis.shortest_wavelength(), lambda_max = spec.basis.longest_wavelength();
    double psf = 0;
    const PinholeCamera& c = t.camera;
    for (const double depth : {t.layers.count > 1 ? 1.0 / t.layers.inverse_depth(t.layers.count - 1) : INFINITY,
                               double(INFINITY)})
        for (const bool corner : {false, true})
            for (const double wavelength : {lambda_min, lambda_max}) {
                FieldPsfRequest q;
                q.aperture = spec.aperture;
                q.film_distance = c.film_distance;
                q.depth = depth;
                q.wavelength = wavelength;
                if (corner)
                    c.tangent(detail::anchor_axis(t, false).knots.front() - t.origin,
                              detail::anchor_axis(t, true).knots.front() - t.origin, q.u, q.v);
                q.pixel_pitch = c.pixel_pitch();
                const double cos_anchor = 1.0 / std::sqrt(1.0 + q.u * q.u + q.v * q.v);
                q.radius = psf_kernel_radius({q.aperture, q.film_distance, q.depth, q.wavelength, cos_anchor},
                                             q.pixel_pitch, t.radius);
                psf = std::max(psf, field_psf_scratch_bytes(q));
            }
    // the larger of two stages: the table built and transformed, and the tiles convolved
    return std::max(kernels + (kept ? spectra : 0) + t.nthreads * psf, (kept ? spectra : kernels) + domain + tiles);
}

Result<std::shared_ptr<const ConvolutionPlan>> ConvolutionPlan::create(const ConvolutionPlanSpec& spec, const ProgressFn& progress) {
    using R = Result<std::shared_ptr<const ConvolutionPlan>>;
    auto geometry = plan_geometry(spec);
    if (!geometry.ok()) return R::failure(geometry.error);
    detail::KernelTableSpec& t = geometry.value.t;
    auto impl = std::make_unique<Impl>(Impl{spec, t, std::nullopt, std::nullopt});
    impl->geometry.basis = &impl->spec.basis;  // (the plan's own copy, not the caller's)
    if (geometry.value.cell > 0) {
        auto conv = detail::DirectionConvolution::create(t, geometry.value.cell, progress);
        if (!conv.ok()) return R::failure(conv.error);
        impl->directions = std::move(conv.value);
    } else {
        // progress: the kernel table is most of the work, the kernels' transforms the rest
        auto table = detail::build_kernel_table(t, progress_slice(progress, 0.0, 0.8));
        if (!table.ok()) return R::failure(table.error);
        auto conv = detail::AnchoredConvolution::create(std::move(table.value), t.tile, t.tiles_on_cells, t.domain_width,
                                                        t.domain_height, t.nthreads, spec.settings.tile_memory,
                                                        progress_slice(progress, 0.8, 1.0));
        if (!conv.ok()) return R::failure(conv.error);
        impl->anchored = std::move(conv.value);
    }
    return R::success(std::shared_ptr<const ConvolutionPlan>(new ConvolutionPlan(std::move(impl))));
}

bool ConvolutionPlan::serves(const ConvolutionPlanSpec& s) const {
    const ConvolutionPlanSpec& p = impl_->spec;
    if (!(same_camera(s.camera, p.camera) && s.overscan == p.overscan && s.aperture.name() == p.aperture.name() &&
          s.aperture.diameter == p.aperture.diameter && s.settings.tile == p.settings.tile &&
          s.settings.max_radius == p.settings.max_radius && s.settings.anchor_cells == p.settings.anchor_cells &&
          s.settings.tile_memory == p.settings.tile_memory &&
          same_basis(s.basis, p.basis)))
        return false;
    // the frame's depth range must lead to this very plan (kernel radius, layers, tiles, the
    // evaluation), so that a frame's image never depends on the frames before it
    auto g = plan_geometry(s);
    const detail::KernelTableSpec& n = g.value.t, &t = impl_->geometry;
    return g.ok() && n.radius == t.radius && n.layers.count == t.layers.count && n.layers.step == t.layers.step &&
           n.tile == t.tile && n.tiles_on_cells == t.tiles_on_cells && (g.value.cell > 0) == impl_->directions.has_value() &&
           (!impl_->directions || g.value.cell == impl_->directions->grid().cell);
}

Result<bool> ConvolutionPlan::apply(const SpectralScene& scene, bool vignetting, float* xyz, const ProgressFn& progress) const {
    const ConvolutionPlanSpec& spec = impl_->spec;
    const PinholeCamera& c = spec.camera;
    if (!same_camera(scene.camera, c)) return Result<bool>::failure("image: not the camera this plan was made for");
    const detail::KernelTable& table = impl_->tail_table();
    const int R = impl_->geometry.radius, o = spec.overscan, origin = impl_->geometry.origin;
    const int out_w = c.width - 2 * o, out_h = c.height - 2 * o;

    // The sources on the domain: the input where it reaches, its edge continued beyond.
    const EdgeContinuation edge(scene.rgb, 3, c.width, c.height);
    detail::DomainSources src;
    src.width = out_w + 2 * R;
    src.height = out_h + 2 * R;
    src.frame = &edge;
    src.origin = origin;
    src.u = detail::column_tangents(c, -origin, src.width);
    src.v = detail::row_tangents(c, -origin, src.height);
    const size_t n = size_t(src.width) * src.height;
    const int threads = detail::thread_count(spec.settings.nthreads);
    std::fill(xyz, xyz + 3 * size_t(out_w) * out_h, 0.0f);
    const detail::OutputWindow window{R, R, out_w, out_h};
    double kernel_edge = 0;
    if (impl_->directions) {  // (one layer: only the sources' light is read)
        if (auto r = impl_->directions->apply(src, window, xyz, progress); !r.ok()) return r;
        kernel_edge = impl_->directions->kernel_edge();
    } else {
        src.lower.resize(n);
        src.upper_share.resize(n);
        detail::parallel_for(0, src.height, threads, [&](int64_t row) {
            const int j = int(row);
            const int cj = std::clamp(j - origin, 0, c.height - 1);
            for (int i = 0; i < src.width; ++i) {
                const int ci = std::clamp(i - origin, 0, c.width - 1);
                const size_t p = size_t(j) * src.width + i, q = size_t(cj) * c.width + ci;
                const double d = scene.depth[q];
                const double w = d >= kInfiniteDepth ? 0.0 : 1.0 / c.planar_depth(ci, cj, d, scene.depth_meaning);
                int lower = 0;
                table.layers.locate(w, lower, src.upper_share[p]);
                src.lower[p] = uint8_t(lower);
            }
        });
        if (auto r = impl_->anchored->apply(src, window, xyz, progress); !r.ok()) return r;
        kernel_edge = detail::film_kernel_edge(R, c.tan_pitch());
    }
    detail::add_far_tail(table, kernel_edge, impl_->directions.has_value(), scene, origin, window, xyz, threads);
    if (!vignetting)
        for (int j = 0; j < out_h; ++j)
            for (int i = 0; i < out_w; ++i) {
                const float k = float(c.cos4(i + o, j + o));
                for (int q = 0; q < 3; ++q) xyz[3 * (size_t(j) * out_w + i) + q] /= k;
            }
    return Result<bool>::success(true);
}

Result<bool> diffract_convolution(const SpectralScene& scene, const SpectralBasis& basis, const Aperture& aperture,
                                  const XyzOutput& out, const ConvolutionSettings& settings,
                                  const ProgressFn& progress) {
    if (!scene.checked)
        if (auto v = check_pixels(scene.camera, scene.rgb, 3, false, scene.depth); !v.ok()) return v;
    const double nearest = nearest_depth(scene.camera, scene.depth, scene.depth_meaning);
    ConvolutionPlanSpec spec{scene.camera, 0, aperture, basis, 1.0 / nearest, settings};
    auto plan = ConvolutionPlan::create(spec, progress_slice(progress, 0.0, 0.5));
    if (!plan.ok()) return Result<bool>::failure(plan.error);
    return plan.value->apply(scene, out.vignetting, out.xyz, progress_slice(progress, 0.5, 1.0));
}

}  // namespace wavecam
