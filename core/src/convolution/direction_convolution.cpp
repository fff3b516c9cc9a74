#include "convolution/direction_convolution.h"

#include <algorithm>
#include <cmath>

#include "base/parallel.h"
#include "base/progress_ticker.h"
#include "convolution/direction_cosines.h"
#include "fft/real_fft2d.h"
#include "wavecam/fresnel_psf.h"

namespace wavecam::detail {

namespace {

// The on-axis PSF request of wavelength s on cells of `cell` axis pixels. The sky's: within
// kMaxFraunhoferPhase a nearer source's defocus moves little light, and its geometric shadow
// a (1 + f / z) is then at most a sixth of the Airy radius (a^2 / z <= 0.3 lambda / pi).
FieldPsfRequest on_axis(const KernelTableSpec& spec, double cell, int s, int radius) {
    FieldPsfRequest q;
    q.aperture = spec.aperture;
    q.film_distance = spec.camera.film_distance;
    q.wavelength = spec.basis->wavelength(s);
    q.pixel_pitch = cell * spec.camera.pixel_pitch();
    q.radius = psf_kernel_radius({q.aperture, q.film_distance, INFINITY, q.wavelength, 1.0}, q.pixel_pitch, radius);
    return q;
}

}  // namespace

double fraunhofer_cell(const KernelTableSpec& spec, double max_inverse_depth) {
    const double a = spec.aperture.bounding_radius(), lambda = spec.basis->shortest_wavelength();
    if (DepthLayers::rim_phase(std::max(0.0, max_inverse_depth), a, lambda, spec.camera.film_distance) >
        kMaxFraunhoferPhase)
        return 0;
    // the core's standard deviation, 0.42 lambda f / D on the film (a Gaussian fitted to the
    // Airy disc's), in axis pixels; a pupil of span D = 2a has no narrower core
    const double sigma = 0.42 * lambda / (2 * a * spec.camera.tan_pitch());
    return sigma >= kCorePixels ? sigma / kCoreCells : 0.0;
}

DirectionGrid DirectionGrid::covering(const KernelTableSpec& spec, double cell) {
    const PinholeCamera& c = spec.camera;
    const DirectionCosines dc{c.tan_pitch()};
    DirectionGrid g;
    g.cell = cell;
    // the output frame's directions (b downward: the up axis's extremes negated)
    const int R = spec.radius;
    const DirectionBox box =
        direction_box(c, dc, R - spec.origin, R - spec.origin, spec.domain_width - 2 * R, spec.domain_height - 2 * R);
    const double lo_a = box.lo_a, hi_a = box.hi_a, lo_b = -box.hi_b, hi_b = -box.lo_b;
    // kernels as wide as the on-axis PSF's share kPsfKernelEnergy needs, within the plan's radius
    g.radius = std::max(1, psf_kernel_radius({spec.aperture, c.film_distance, INFINITY, spec.basis->longest_wavelength(), 1.0},
                                             cell * c.pixel_pitch(), std::max(1, int(std::floor(R / cell)))));
    // the grid: the output's directions widened by the kernels' reach and two cells for the
    // bilinear spread and read, within the disc of directions (no film point lies beyond it)
    const double reach = (g.radius + 2) * cell, disc = 1 / dc.pitch;
    g.a0 = std::max(-disc, lo_a - reach);
    g.b0 = std::max(-disc, lo_b - reach);
    g.width = int(std::ceil((std::min(disc, hi_a + reach) - g.a0) / cell)) + 1;
    g.height = int(std::ceil((std::min(disc, hi_b + reach) - g.b0) / cell)) + 1;
    // The period: light spread past one side of the grid wraps round to the other, and must land
    // beyond the output's cells there: longer than the grid where the disc cuts it short.
    auto period = [&](int cells, double lo, double hi, double start) {
        const int K = g.radius + 1, first = int(std::floor((lo - start) / cell)), last = int(std::ceil((hi - start) / cell));
        return fft_friendly_size(std::max({cells, cells + K - first, last + K + 1}));
    };
    g.fft_width = period(g.width, lo_a, hi_a, g.a0);
    g.fft_height = period(g.height, lo_b, hi_b, g.b0);
    return g;
}

void DirectionGrid::position(const DirectionCosines& dc, double u, double v, double& x, double& y) const {
    double ax, ay;
    dc.of_tangent(u, v, ax, ay);
    x = (ax - a0) / cell;
    y = (-ay - b0) / cell;
}

Result<DirectionConvolution> DirectionConvolution::create(const KernelTableSpec& spec, double cell,
                                                          const ProgressFn& progress) {
    using R = Result<DirectionConvolution>;
    DirectionConvolution d;
    d.grid_ = DirectionGrid::covering(spec, cell);
    d.camera_ = spec.camera;
    d.nthreads_ = spec.nthreads;
    const DirectionGrid& g = d.grid_;
    const SpectralBasis& basis = *spec.basis;
    const int S = basis.size(), K = g.radius, kw = 2 * K + 1;
    // the PSFs, longest wavelength first, on shared transfer grids (the shorter ones on its grid
    // find its pupil spectrum kept, share_transfer_grids)
    std::vector<FieldPsfRequest> requests(S);
    for (int s = 0; s < S; ++s) requests[s] = on_axis(spec, cell, s, K);
    share_transfer_grids(requests);
    std::vector<int> order(S);
    for (int s = 0; s < S; ++s) order[s] = s;
    std::sort(order.begin(), order.end(), [&](int x, int y) { return basis.wavelength(x) > basis.wavelength(y); });
    std::vector<PsfKernel> psf(S);
    const ProgressFn psf_progress = progress_slice(progress, 0.0, 0.8);
    ProgressTicker ticker(psf_progress, S);
    parallel_for_dynamic(0, S, 1, thread_count(spec.nthreads), [&](int64_t k) {
        if (ticker.cancelled()) return;
        const int s = order[size_t(k)];
        psf[s] = field_psf_kernel(requests[s]);
        ticker.advance(1, on_calling_thread());
    });
    if (ticker.cancelled()) return R::failure("cancelled", ErrorKind::Cancelled);
    // folded into the nine kernels, and their deficits as every anchor's of the far tail's table
    LargeArray<float> kernels(size_t(9) * kw * kw);
    std::fill_n(&kernels[0], kernels.size(), 0.0f);
    float* each[9];
    for (int m = 0; m < 9; ++m) each[m] = &kernels[size_t(m) * kw * kw];
    float deficit[9] = {};
    for (int s = 0; s < S; ++s) {
        add_wavelength(psf[s], basis, s, K, each, deficit);
        psf[s] = {};
    }
    KernelTable& tail = d.tail_;
    tail.radius = spec.radius;
    tail.layers = spec.layers;
    tail.ax = AnchorAxis::even(spec.radius, spec.domain_width - 2 * spec.radius, 1);
    tail.ay = AnchorAxis::even(spec.radius, spec.domain_height - 2 * spec.radius, 1);
    for (int a = 0; a < tail.layers.count * tail.anchors(); ++a) tail.deficit.insert(tail.deficit.end(), deficit, deficit + 9);
    // the kernels' spectra, each kernel centred on the origin and wrapped
    const int Nx = g.fft_width, Ny = g.fft_height;
    RealFft2D fft(Nx, Ny);
    if (!fft.ok())
        return R::failure("fft: cannot set up a " + std::to_string(Nx) + " x " + std::to_string(Ny) + "-point transform");
    fft.set_threads(thread_count(spec.nthreads));
    d.spectrum_size_ = fft.spectrum_size();
    d.kernel_spectra_ = LargeArray<std::complex<float>>(9 * d.spectrum_size_);
    LargeArray<float> image(size_t(Nx) * Ny);
    std::fill_n(&image[0], image.size(), 0.0f);
    for (int m = 0; m < 9; ++m) {
        transform_centred_kernel(each[m], K, fft, Nx, Ny, &image[0], &d.kernel_spectra_[size_t(m) * d.spectrum_size_],
                                 thread_count(spec.nthreads));
        if (progress) progress(0.8 + 0.2 * (m + 1) / 9.0);
    }
    return R::success(std::move(d));
}

Result<bool> DirectionConvolution::apply(const DomainSources& src, const OutputWindow& out, float* xyz,
                                         const ProgressFn& progress) const {
    const DirectionGrid& g = grid_;
    const DirectionCosines dc{camera_.tan_pitch()};
    const int Nx = g.fft_width, Ny = g.fft_height, threads = thread_count(nthreads_);
    const size_t points = size_t(Nx) * Ny, n = spectrum_size_;
    ProgressTicker ticker(progress, 5);  // the spread, the transforms, three channels
    // 1. the sources' light spread over the grid, each thread its own grids (summed in order:
    // the same image at any schedule of a given thread count)
    std::vector<std::vector<float>> part(size_t(threads), std::vector<float>(3 * points, 0.0f));
    // a source's light at grid position (x, y) over the four cells round it (none where they
    // are not all on the grid: such a source lies beyond the kernels' reach of the output)
    auto spread = [&](double x, double y, float* grids, auto light) {
        const int I = int(std::floor(x)), J = int(std::floor(y));
        if (I < 0 || J < 0 || I + 1 >= g.width || J + 1 >= g.height) return;
        const float tx = float(x - I), ty = float(y - J);
        const float w[4] = {(1 - tx) * (1 - ty), tx * (1 - ty), (1 - tx) * ty, tx * ty};
        const size_t at[4] = {size_t(J) * Nx + I, size_t(J) * Nx + I + 1, size_t(J + 1) * Nx + I,
                              size_t(J + 1) * Nx + I + 1};
        for (int p = 0; p < 3; ++p) {
            const float l = light(p);
            if (l == 0) continue;
            float* grid = grids + p * points;
            for (int k = 0; k < 4; ++k) grid[at[k]] += w[k] * l;
        }
    };
    parallel_team(threads, [&](Team& team) {
        float* mine = part[size_t(team.rank())].data();
        team.for_blocks(0, src.height, [&](int64_t j) {
            for (int i = 0; i < src.width; ++i) {
                double x, y;
                g.position(dc, src.u[i], src.v[size_t(j)], x, y);
                const float oblique = float(std::sqrt(1 + src.u[i] * src.u[i] + src.v[size_t(j)] * src.v[size_t(j)]));
                spread(x, y, mine, [&](int p) { return src.light(i, int(j), p) * oblique; });
            }
        });
        // beyond the domain, the edge continued (edge_continuation.h) where the grid reaches:
        // 2 x 2 points a cell, each the light of its quarter of a cell (radiance x its area in
        // axis pixels, as a pixel's light is radiance x its cos^4), times 1 / cos(in) integrated
        // over the quarter's radial extent within the disc, [r0, r1], per its width: (asin r1 -
        // asin r0) / width (1 / cos = (1 - r^2)^-1/2 grows without bound at the disc's edge,
        // where a point's value would not stand for its quarter)
        const PinholeCamera& c = camera_;
        const double quarter = 0.25 * g.cell * g.cell, half_width = 0.25 * g.cell * dc.pitch;
        team.for_blocks(0, g.height, [&](int64_t J) {
            for (int I = 0; I < g.width; ++I)
                for (int k = 0; k < 4; ++k) {
                    const double x = I - 0.25 + 0.5 * (k & 1), y = double(J) - 0.25 + 0.5 * (k >> 1);
                    const double ax = g.a0 + x * g.cell, ay = -(g.b0 + y * g.cell);
                    const double r = std::hypot(ax, ay) * dc.pitch, r0 = r - half_width, r1 = std::min(1.0, r + half_width);
                    if (r0 >= 1) continue;
                    double u, v;  // (the quarter's centre, or where it lies beyond the disc its inner edge's direction)
                    const double inside = r < 1 ? 1.0 : r0 / r;
                    if (!dc.to_tangent(ax * inside, ay * inside, u, v)) continue;
                    const double fx = u / dc.pitch + 0.5 * c.width, fy = 0.5 * c.height - v / dc.pitch;
                    const double dx = fx + src.origin, dy = fy + src.origin;  // in the domain's pixels
                    if (dx >= 0 && dx < src.width && dy >= 0 && dy < src.height) continue;
                    const float* rgb = src.frame->light(int(std::floor(fx)), int(std::floor(fy)));
                    const double oblique = (std::asin(r1) - std::asin(r0)) / (2 * half_width);
                    spread(x, y, mine, [&](int p) { return float(rgb[p] * quarter * oblique); });
                }
        });
    });
    for (size_t t = 1; t < part.size(); ++t)
        for (size_t k = 0; k < 3 * points; ++k) part[0][k] += part[t][k];
    for (size_t t = 1; t < part.size(); ++t) part[t] = {};
    if (ticker.cancelled()) return Result<bool>::failure("cancelled", ErrorKind::Cancelled);
    ticker.advance(1, true);
    // 2. each primary's spectrum
    RealFft2D fft(Nx, Ny);
    fft.set_threads(threads);
    LargeArray<std::complex<float>> light(3 * n), acc(n);
    for (int p = 0; p < 3; ++p) fft.forward(&part[0][size_t(p) * points], &light[size_t(p) * n]);
    ticker.advance(1, true);
    // 3. per XYZ channel: the primaries times their kernels, back to the grid, read at each
    // pixel's direction over a cell's area, times the pixel's own area (cos^4 axis pixels)
    const float scale = float(1.0 / double(points));
    const double per_area = 1.0 / (g.cell * g.cell);
    float* image = part[0].data();  // (the spread light is no longer needed)
    for (int q = 0; q < 3; ++q) {
        if (ticker.cancelled()) return Result<bool>::failure("cancelled", ErrorKind::Cancelled);
        parallel_for(0, int64_t(n), threads, [&](int64_t k) {
            std::complex<float> sum = 0;
            for (int p = 0; p < 3; ++p) sum += kernel_spectra_[size_t(3 * p + q) * n + size_t(k)] * light[size_t(p) * n + size_t(k)];
            acc[size_t(k)] = sum * scale;
        });
        fft.inverse(&acc[0], image);
        parallel_for(0, out.height, threads, [&](int64_t j) {
            const double v = src.v[size_t(out.y0 + j)];
            for (int i = 0; i < out.width; ++i) {
                const double u = src.u[size_t(out.x0 + i)];
                double x, y;
                g.position(dc, u, v, x, y);
                const int I = int(std::floor(x)), J = int(std::floor(y));
                const double tx = x - I, ty = y - J;
                auto at = [&](int ii, int jj) { return double(image[size_t(jj) * Nx + ii]); };
                const double value = (1 - ty) * ((1 - tx) * at(I, J) + tx * at(I + 1, J)) +
                                     ty * ((1 - tx) * at(I, J + 1) + tx * at(I + 1, J + 1));
                const double c2 = 1.0 / (1 + u * u + v * v);  // (cos^4 x cos: c2^2.5)
                xyz[3 * (size_t(j) * out.width + i) + q] += float(value * per_area * c2 * c2 * std::sqrt(c2));
            }
        });
        ticker.advance(1, true);
    }
    return Result<bool>::success(true);
}

double DirectionConvolution::estimate_bytes(const KernelTableSpec& spec, double cell) {
    const DirectionGrid g = DirectionGrid::covering(spec, cell);
    const double points = double(g.fft_width) * g.fft_height, spectrum = g.fft_width * (g.fft_height / 2 + 1) * 8.0;
    const double kernel = std::pow(2.0 * g.radius + 1, 2) * sizeof(float);
    const int threads = thread_count(spec.nthreads);
    // creating: the PSFs, each thread's working memory for one, the nine kernels, their spectra
    double psf = 0;
    for (int s = 0; s < spec.basis->size(); ++s)
        psf = std::max(psf, field_psf_scratch_bytes(on_axis(spec, cell, s, g.radius)));
    const double create = spec.basis->size() * kernel + threads * psf + 9 * kernel + 9 * spectrum + points * 4;
    // applying: the kernels' spectra, the spread light (a set per thread), the primaries'
    // spectra and one channel's, and the transform's own two arrays
    const double apply = 9 * spectrum + threads * 3 * points * 4 + 4 * spectrum + 2 * spectrum;
    return std::max(create, apply);
}

}  // namespace wavecam::detail
