#include "convolution/kernel_table.h"


#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>

#include "base/parallel.h"
#include "base/progress_ticker.h"
#include "wavecam/fresnel_psf.h"

namespace wavecam::detail {

namespace {
constexpr double kMaxDefocusStep = 0.3;  // radians of defocus phase over the pinhole between layers
constexpr double kMaxBlurStep = 0.5;     // pixels of blur-disc radius between layers
constexpr double kGeometricZones = 8;    // Fresnel zones from which the PSF is the blur disc
constexpr int kMaxLayers = 16;
}  // namespace

DepthLayers DepthLayers::spanning(double max_inverse_depth, double aperture_radius, double shortest_wavelength,
                                  double film_distance, double pixel_pitch) {
    DepthLayers d;
    if (!(max_inverse_depth > 0)) return d;
    // defocus phase pi a^2 dw / lambda <= kMaxDefocusStep; or, for pinholes in the geometric
    // regime (at least kGeometricZones Fresnel zones a^2 / (lambda f) even for the sky), the
    // blur disc's radius a (1 + f w) changing by at most kMaxBlurStep pixels
    const double defocus = kMaxDefocusStep * shortest_wavelength / (M_PI * aperture_radius * aperture_radius);
    const bool geometric = aperture_radius * aperture_radius / (shortest_wavelength * film_distance) >= kGeometricZones;
    const double dw = geometric ? std::max(defocus, kMaxBlurStep * pixel_pitch / (aperture_radius * film_distance))
                                : defocus;
    // Layers sit at whole multiples of the step, which depends on the frame only through how
    // many steps its nearest source needs: frames of a sequence then share a plan and each
    // frame's image is the one a plan of its own gives. Beyond kMaxLayers, whole multiples of dw.
    const double multiple = std::ceil(max_inverse_depth / (dw * (kMaxLayers - 1)));  // (double: no overflow)
    d.step = dw * multiple;
    d.count = int(std::ceil(max_inverse_depth / d.step)) + 1;
    // One layer (the sky's) serves every depth where the defocus phase at the rim, pi a^2 (w +
    // 1/f) / lambda, stays within kMaxDefocusStep even at the nearest source: a defocus phi
    // rho^2 over a disc has phase variance phi^2 / 12, and by Marechal's rule the PSF then
    // moves at most that share of its light (0.75% at 0.3 rad) - small pinholes, whose Airy
    // disc no depth changes.
    if (rim_phase(max_inverse_depth, aperture_radius, shortest_wavelength, film_distance) <= kMaxDefocusStep)
        d.count = 1;
    return d;
}

void DepthLayers::locate(double w, int& lower, float& upper_share) const {
    const double x = count > 1 ? w / step : 0.0;
    lower = std::clamp(int(std::floor(x)), 0, count - 1);
    upper_share = lower + 1 < count ? float(std::min(1.0, x - lower)) : 0.0f;
}

double anchor_step(const Aperture& aperture, double longest_wavelength, double film_distance, double pixel_pitch) {
    const double span = 2 * aperture.bounding_radius();
    const double airy = 1.22 * longest_wavelength * film_distance / span, shadow = span / 2;
    // diffraction's share of the PSF's variance, times the PSF's share of the PSF's and pixel's
    const double share = airy * airy / (airy * airy + shadow * shadow + pixel_pitch * pixel_pitch / 12);
    return kMaxAnchorStep / std::sqrt(std::max(share, 0.25));  // (at most twice as wide: the shadow's rim)
}

int AnchorAxis::cell_of(int pixel) const {
    const auto it = std::upper_bound(knots.begin(), knots.end(), pixel);
    return std::clamp(int(it - knots.begin()) - 1, 0, cells() - 1);
}

int AnchorAxis::cell_count(int span, int ripple, int min_cell, double tan_pitch, double max_step) {
    return std::max(std::min(ripple, span / std::max(1, min_cell)), int(std::ceil(span * tan_pitch / max_step - 1e-9)));
}

AnchorAxis AnchorAxis::even(int inset, int span, int cells) {
    int n = std::clamp(cells, 1, std::max(1, span));
    // an odd span has its middle between pixels, where no knot can lie: an odd count of cells
    if (span % 2 == 1 && n % 2 == 0) ++n;
    AnchorAxis a;
    a.knots.resize(n + 1);
    // the lower half rounded, the upper half its mirror image: knots k and n - k sum to the span
    for (int k = 0; 2 * k <= n; ++k) {
        a.knots[k] = inset + int(std::floor(double(k) * span / n + 0.5));
        a.knots[n - k] = 2 * inset + span - a.knots[k];
    }
    return a;
}

AnchorAxis anchor_axis(const KernelTableSpec& spec, bool vertical) {
    const int length = vertical ? spec.domain_height : spec.domain_width, span = length - 2 * spec.radius;
    const int ripple = vertical ? std::max(1, int(std::lround(double(spec.anchor_cells) * length /
                                                              std::max(spec.domain_width, spec.domain_height))))
                                : spec.anchor_cells;
    const PinholeCamera& c = spec.camera;
    const double step = anchor_step(spec.aperture, spec.basis->longest_wavelength(), c.film_distance, c.pixel_pitch());
    const int cells = AnchorAxis::cell_count(span, ripple, kMinCellRadii * spec.radius, c.tan_pitch(), step);
    return AnchorAxis::even(spec.radius, span, cells);
}

namespace {

// Knot k's mirror image across the optical axis (camera position `axis2` / 2, in the domain's
// pixels), or k itself where the knots are not mirror-symmetric or the aperture is not even.
std::vector<int> mirror_knots(const AnchorAxis& a, int axis2, bool even) {
    const int n = int(a.knots.size());
    std::vector<int> mirror(n);
    bool symmetric = even;
    for (int k = 0; k < n; ++k) symmetric &= a.knots[k] + a.knots[n - 1 - k] == axis2;
    for (int k = 0; k < n; ++k) mirror[k] = symmetric ? n - 1 - k : k;
    return mirror;
}

}  // namespace

std::vector<int> mirror_sources(const AnchorAxis& ax, const AnchorAxis& ay, int axis2x, int axis2y, bool even_x,
                                bool even_y) {
    const std::vector<int> mx = mirror_knots(ax, axis2x, even_x), my = mirror_knots(ay, axis2y, even_y);
    const int nkx = int(ax.knots.size());
    std::vector<int> source(ax.knots.size() * ay.knots.size());
    // an anchor whose mirror image has the lower index takes its kernels mirrored
    for (int a = 0; a < int(source.size()); ++a)
        source[a] = std::min(a / nkx, my[a / nkx]) * nkx + std::min(a % nkx, mx[a % nkx]);
    return source;
}

std::vector<int> anchor_sources(const KernelTableSpec& spec, const AnchorAxis& ax, const AnchorAxis& ay) {
    // (a knot is a point in the camera's pixel coordinates plus origin: the axis at width / 2)
    const PinholeCamera& c = spec.camera;
    return mirror_sources(ax, ay, c.width + 2 * spec.origin, c.height + 2 * spec.origin, spec.aperture.even_in_x(),
                          spec.aperture.even_in_y());
}

int computed_anchors(const KernelTableSpec& spec, const AnchorAxis& ax, const AnchorAxis& ay) {
    const std::vector<int> source = anchor_sources(spec, ax, ay);
    int n = 0;
    for (int a = 0; a < int(source.size()); ++a) n += source[a] == a;
    return n;
}

void add_wavelength(const PsfKernel& psf, const SpectralBasis& basis, int s, int radius, float* const kernels[9],
                    float* deficit) {
    const int inset = radius - psf.radius, pw = 2 * psf.radius + 1, tw = 2 * radius + 1;
    const Vector3& xyz_s = basis.xyz_per_power(s);
    double held = 0;  // the weights are shares of the PSF's power: what lies beyond is 1 - held
    for (float x : psf.weight) held += x;
    for (int p = 0; p < 3; ++p) {
        const double bp = basis.power(s, p == 0, p == 1, p == 2);
        for (int qq = 0; qq < 3; ++qq) {
            const float w = float(bp * xyz_s[qq]);
            deficit[3 * p + qq] += float(w * (1.0 - held));
            float* dst = kernels[3 * p + qq];
            for (int b = 0; b < pw; ++b)
                for (int e = 0; e < pw; ++e)
                    dst[size_t(b + inset) * tw + (e + inset)] += w * psf.weight[size_t(b) * pw + e];
        }
    }
}

Result<KernelTable> build_kernel_table(const KernelTableSpec& spec, const ProgressFn& progress) {
    KernelTable t;
    t.radius = spec.radius;
    t.layers = spec.layers;
    t.ax = anchor_axis(spec, false);
    t.ay = anchor_axis(spec, true);
    const int anchors = t.anchors(), S = spec.basis->size(), nkx = int(t.ax.knots.size());
    const size_t ksize = t.kernel_size();
    const PinholeCamera& c = spec.camera;
    t.source = anchor_sources(spec, t.ax, t.ay);
    t.slot.assign(anchors, -1);
    for (int a = 0; a < anchors; ++a)
        if (t.source[a] == a) t.slot[a] = t.computed++;
    t.weights = LargeArray<float>(size_t(t.layers.count) * t.computed * 9 * ksize);
    t.deficit.assign(size_t(t.layers.count) * anchors * 9, 0.0f);
    std::vector<long> computed;
    for (long g = 0; g < long(t.layers.count) * anchors; ++g)
        if (t.source[g % anchors] == g % anchors) computed.push_back(g);
    const long grid = long(computed.size());
    // Every PSF's request, (grid entry, wavelength); a layer's requests share their transfer
    // grids (share_transfer_grids: one layer, one pupil spectrum a grid size)
    std::vector<FieldPsfRequest> requests(size_t(grid) * S);
    for (long i = 0; i < grid; ++i) {
        const int l = int(computed[size_t(i)] / anchors), a = int(computed[size_t(i)] % anchors);
        FieldPsfRequest q;
        q.aperture = spec.aperture;
        q.film_distance = c.film_distance;
        q.depth = t.layers.inverse_depth(l) > 0 ? 1.0 / t.layers.inverse_depth(l) : INFINITY;
        // the anchor's field position: its knot, in the camera's pixel coordinates
        c.tangent(t.ax.knots[a % nkx] - spec.origin, t.ay.knots[a / nkx] - spec.origin, q.u, q.v);
        q.pixel_pitch = c.pixel_pitch();
        const double cos_anchor = 1.0 / std::sqrt(1.0 + q.u * q.u + q.v * q.v);
        // each PSF only as large as its own depth, field angle and wavelength need (the cost
        // grows as its area), centred in the table's common size
        for (int s = 0; s < S; ++s) {
            q.wavelength = spec.basis->wavelength(s);
            q.radius = psf_kernel_radius({q.aperture, q.film_distance, q.depth, q.wavelength, cos_anchor},
                                         q.pixel_pitch, t.radius);
            requests[size_t(i) * S + s] = q;
        }
    }
    for (long i0 = 0; i0 < grid;) {  // (computed entries are in layer order)
        long i1 = i0;
        while (i1 < grid && computed[size_t(i1)] / anchors == computed[size_t(i0)] / anchors) ++i1;
        std::vector<FieldPsfRequest> layer(requests.begin() + i0 * S, requests.begin() + i1 * S);
        share_transfer_grids(layer);
        std::copy(layer.begin(), layer.end(), requests.begin() + i0 * S);
        i0 = i1;
    }
    ProgressTicker ticker(progress, double(grid) * S);
    auto compute_entry = [&](int64_t i) {
        if (ticker.cancelled()) return;
        const long g = computed[size_t(i)];
        const int l = int(g / anchors), a = int(g % anchors);
        const FieldPsfRequest* q = &requests[size_t(i) * S];
        // The rows the anchor's nine kernels will hold written (zeros) before the wavelengths add
        // to them: a fresh page first touched by a read maps the shared zero page, and the write
        // after it then copies that page and interrupts every other thread's processor to flush
        // its TLB (a 0.02 mm frame spent a sixth of its time in those interrupts).
        int widest = 0;
        for (int s = 0; s < S; ++s) widest = std::max(widest, q[s].radius);
        const int tw = 2 * t.radius + 1;
        for (int k = 0; k < 9; ++k)
            std::fill_n(&t.weights[size_t(t.kernel_index(l, a, k)) * ksize + size_t(t.radius - widest) * tw],
                        size_t(2 * widest + 1) * tw, 0.0f);
        // longest wavelength first: its transfer grid is the widest, and the shorter ones on the
        // same grid then find its pupil spectrum kept
        std::vector<int> order(S);
        for (int s = 0; s < S; ++s) order[s] = s;
        std::sort(order.begin(), order.end(),
                  [&](int x, int y) { return spec.basis->wavelength(x) > spec.basis->wavelength(y); });
        for (int s : order) {
            float* kernels[9];
            for (int m = 0; m < 9; ++m) kernels[m] = &t.weights[size_t(t.kernel_index(l, a, m)) * ksize];
            add_wavelength(field_psf_kernel(q[s]), *spec.basis, s, t.radius, kernels,
                           &t.deficit[(size_t(l) * anchors + a) * 9]);
            ticker.advance(1, on_calling_thread());
        }
    };
    // Each thread computes its own contiguous run of the entries (layer after layer), then what
    // is left of the others' runs, from their far ends: each layer's pupil spectra (one a grid
    // size, kept per thread) are then computed by one thread, where threads taking the entries
    // in turn each computed all of them. Entries write only their own kernels: the same table
    // whichever thread computes an entry.
    const int threads = int(std::min<long>(thread_count(spec.nthreads), std::max(grid, 1L)));
    std::unique_ptr<std::atomic<bool>[]> taken(new std::atomic<bool>[size_t(grid)]);
    for (long i = 0; i < grid; ++i) taken[size_t(i)] = false;
    parallel_team(threads, [&](Team& team) {
        auto run = [&](int k, long& begin, long& end) {
            begin = grid * k / team.size();
            end = grid * (k + 1) / team.size();
        };
        long begin, end;
        run(team.rank(), begin, end);
        for (long i = begin; i < end; ++i)
            if (!taken[size_t(i)].exchange(true)) compute_entry(i);
        for (int k = 1; k < team.size(); ++k) {
            run((team.rank() + k) % team.size(), begin, end);
            for (long i = end - 1; i >= begin; --i)
                if (!taken[size_t(i)].exchange(true)) compute_entry(i);
        }
    });
    if (ticker.cancelled()) return Result<KernelTable>::failure("cancelled", ErrorKind::Cancelled);
    for (int l = 0; l < t.layers.count; ++l)
        for (int a = 0; a < anchors; ++a) {
            const int from = t.source[a];
            if (from == a) continue;
            const size_t to_k = (size_t(l) * anchors + a) * 9, from_k = (size_t(l) * anchors + from) * 9;
            for (int m = 0; m < 9; ++m) t.deficit[to_k + m] = t.deficit[from_k + m];
        }
    return Result<KernelTable>::success(std::move(t));
}

}  // namespace wavecam::detail
