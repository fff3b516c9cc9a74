#include "convolution/anchored_convolution.h"


#include <algorithm>
#include <atomic>
#include <memory>

#include "convolution/output_window.h"
#include "base/parallel.h"
#include "base/progress_ticker.h"
#include "fft/real_fft2d.h"

namespace wavecam::detail {

int convolution_fft_length(int tile, int radius, int length) {
    return fft_friendly_size(tile >= length ? length : tile + 2 * radius);
}

std::vector<int> cell_edges(const AnchorAxis& a, int length) {
    std::vector<int> e(a.knots.begin(), a.knots.end());
    e.front() = 0;
    e.back() = length;
    return e;
}

std::vector<int> tile_edges(const AnchorAxis& a, int length, int tile, int radius, bool on_cells) {
    if (tile >= length) return {0, length};  // one tile: its transform wraps into the margin
    std::vector<int> even;
    for (int x = 0; x < length; x += tile) even.push_back(x);
    even.push_back(length);
    if (!on_cells) return even;
    // whole cells joined while they fit in a tile; a cell wider than a tile split evenly
    std::vector<int> edges{0};
    int end = 0;  // the end of the cells joined so far
    for (const int b : cell_edges(a, length)) {
        if (b - edges.back() <= tile) {
            end = b;
            continue;
        }
        if (end > edges.back()) edges.push_back(end);
        end = b;
        if (b - edges.back() <= tile) continue;
        const int from = edges.back(), parts = (b - from + tile - 1) / tile;
        for (int m = 1; m <= parts; ++m) edges.push_back(from + int(std::lround(double(m) * (b - from) / parts)));
    }
    if (end > edges.back()) edges.push_back(end);
    for (size_t k = 0; k + 1 < edges.size(); ++k)
        if (edges[k + 1] - edges[k] < radius) return even;
    return edges;
}

int pass_period(const std::vector<int>& edges, int radius) {
    // tiles k and k + P of one pass write [edges[k] - R, edges[k + 1] + R) and from
    // edges[k + P] - R: apart where the P - 1 tiles between them span 2 R
    const int tiles = int(edges.size()) - 1;
    for (int period = 2;; ++period) {
        bool apart = true;
        for (int k = 0; k + period <= tiles - 1 && apart; ++k) apart = edges[k + period] - edges[k + 1] >= 2 * radius;
        if (apart || period >= tiles) return period;
    }
}

void transform_centred_kernel(const float* w, int R, RealFft2D& fft, int Nx, int Ny, float* image,
                              std::complex<float>* spectrum, int threads) {
    const int kw = 2 * R + 1;
    // the kernel centred on the origin, wrapped
    parallel_for(-R, R + 1, threads, [&](int64_t b) {
        for (int a = -R; a <= R; ++a) image[size_t((b + Ny) % Ny) * Nx + (a + Nx) % Nx] = w[size_t(b + R) * kw + (a + R)];
    });
    fft.forward(image, spectrum, Nx - R, Nx + R + 1);  // (the columns wrap)
    parallel_for(-R, R + 1, threads, [&](int64_t b) {
        for (int a = -R; a <= R; ++a) image[size_t((b + Ny) % Ny) * Nx + (a + Nx) % Nx] = 0.0f;
    });
}

void AnchoredConvolution::transform_kernel(long k, RealFft2D& fft, float* image, std::complex<float>* spectrum,
                                           int threads) const {
    transform_centred_kernel(table_.kernel(k), table_.radius, fft, fft_width_, fft_height_, image, spectrum, threads);
}

Result<AnchoredConvolution> AnchoredConvolution::create(KernelTable table, int tile, bool tiles_on_cells, int width,
                                                        int height, int nthreads, double tile_memory,
                                                        const ProgressFn& progress) {
    AnchoredConvolution c;
    c.tile_memory_ = tile_memory;
    c.tile_ = tile;
    c.tiles_on_cells_ = tiles_on_cells;
    c.fft_width_ = convolution_fft_length(tile, table.radius, width);
    c.fft_height_ = convolution_fft_length(tile, table.radius, height);
    c.nthreads_ = nthreads;
    c.edges_x_ = tile_edges(table.ax, width, tile, table.radius, tiles_on_cells);
    c.edges_y_ = tile_edges(table.ay, height, tile, table.radius, tiles_on_cells);
    c.table_ = std::move(table);
    const KernelTable& t = c.table_;
    const int Nx = c.fft_width_, Ny = c.fft_height_;
    // only the computed anchors' spectra are kept, as the table keeps their kernels: a mirror
    // image's is its source's, reflected as it is read (KernelView)
    const long count = long(t.layers.count) * t.computed * 9;
    {
        RealFft2D probe(Nx, Ny);
        if (!probe.ok())
            return Result<AnchoredConvolution>::failure("fft: cannot set up a " + std::to_string(Nx) + " x " +
                                                        std::to_string(Ny) + "-point transform");
        c.spectrum_size_ = probe.spectrum_size();
    }
    // spectra beyond kMaxKernelSpectraBytes are transformed by each tile that needs them instead,
    // and so are a single tile's (it uses each once)
    if (!keeps_kernel_spectra(count, c.spectrum_size_, (c.edges_x_.size() - 1) * (c.edges_y_.size() - 1))) {
        if (progress) progress(1.0);
        return Result<AnchoredConvolution>::success(std::move(c));
    }
    c.kernel_spectra_ = LargeArray<std::complex<float>>(size_t(count) * c.spectrum_size_);
    ProgressTicker ticker(progress, double(count));
    parallel_team(nthreads, [&](Team& team) {
        RealFft2D fft(Nx, Ny);
        std::vector<float> image(size_t(Nx) * Ny, 0.0f);
        team.for_dynamic(0, count, 4, [&](int64_t k) {
            if (ticker.cancelled()) return;
            c.transform_kernel(k, fft, image.data(), &c.kernel_spectra_[size_t(k) * c.spectrum_size_], 1);
            ticker.advance(1, team.rank() == 0);
        });
    });
    if (ticker.cancelled()) return Result<AnchoredConvolution>::failure("cancelled", ErrorKind::Cancelled);
    c.table_.weights = {};  // the kernels live on as their spectra
    return Result<AnchoredConvolution>::success(std::move(c));
}

AnchoredConvolution::KernelView AnchoredConvolution::spectrum(int layer, int anchor, int m) const {
    const KernelTable& t = table_;
    // spectra kept for ky >= 0 (real_fft2d.h): w(-x, y) has the spectrum X(-kx, ky); w(x, -y) has
    // X(kx, -ky) = conj X(-kx, ky) (real input); both, conj X(kx, ky)
    const bool in_x = t.mirrored_x(anchor), in_y = t.mirrored_y(anchor);
    return {&kernel_spectra_[size_t(t.kernel_index(layer, t.source[anchor], m)) * spectrum_size_], in_x != in_y, in_y};
}

namespace {

// The depth layers the tile's sources touch, [lo, hi] (hi < lo: none).
void layer_span(const DomainSources& src, const TileBounds& b, int layers, int& lo, int& hi) {
    lo = layers;
    hi = -1;
    for (int j = b.y0; j < b.y1; ++j)
        for (int i = b.x0; i < b.x1; ++i) {
            const size_t p = size_t(j) * src.width + i;
            lo = std::min<int>(lo, src.lower[p]);
            hi = std::max<int>(hi, src.lower[p] + (src.upper_share[p] > 0 ? 1 : 0));
        }
}

// One kernel of the table: depth layer `layer` at anchor (kx, ky).
struct LayerAnchor {
    int layer, kx, ky;
};

// The tile's columns [first, last) that an anchor's share lights (none where first >= last).
struct LitColumns {
    int first, last;
};

// Layer l's and anchor (kx, ky)'s share of each source of the tile into `weight` (row by row,
// the tile's width each); the columns it lights (the others are zero in every weighted image).
LitColumns anchor_weights(const KernelTable& t, const DomainSources& src, const TileBounds& b, const LayerAnchor& la,
                          float* weight, int threads) {
    const int T = b.x1 - b.x0;
    const int l = la.layer, kx = la.kx, ky = la.ky;
    std::vector<float> wx(T);  // the hat across, once per column
    for (int i = b.x0; i < b.x1; ++i) wx[i - b.x0] = float(t.ax.hat(kx, i));
    // each row's lit columns, then their union
    std::vector<int> row_first(b.y1 - b.y0, T), row_last(b.y1 - b.y0, 0);
    parallel_for(b.y0, b.y1, threads, [&](int64_t j) {
        const float wy = float(t.ay.hat(ky, int(j)));
        if (wy == 0.0f) {  // a row beyond the hat
            std::fill_n(&weight[size_t(j - b.y0) * T], T, 0.0f);
            return;
        }
        int& first = row_first[j - b.y0];
        int& last = row_last[j - b.y0];
        for (int i = b.x0; i < b.x1; ++i) {
            const size_t q = size_t(j) * src.width + i;
            const float share = src.lower[q] == l         ? 1.0f - src.upper_share[q]
                                : src.lower[q] + 1 == l ? src.upper_share[q]
                                                        : 0.0f;
            const float w = share * wy * wx[i - b.x0];
            weight[size_t(j - b.y0) * T + (i - b.x0)] = w;
            if (w > 0) {
                first = std::min(first, i - b.x0);
                last = std::max(last, i - b.x0 + 1);
            }
        }
    });
    return {*std::min_element(row_first.begin(), row_first.end()), *std::max_element(row_last.begin(), row_last.end())};
}

// acc += in K: one primary's spectrum times one kernel's, added to one channel's accumulated
// spectrum (acc_q = sum_p in_p K_{3p+q}), written on floats so that it vectorises
// (std::complex's operator* keeps a NaN-recovery branch); spectra of N rows (kx) of `half`
// (ky >= 0; a kernel's rows read as N - r where it is its source's mirror image).
void multiply_add(const std::complex<float>* in, const AnchoredConvolution::KernelView& kv, std::complex<float>* acc,
                  int N, int half, int threads) {
    const float sign = kv.conjugate ? -1.0f : 1.0f;
    parallel_for(0, N, threads, [&](int64_t r) {
        float* a = reinterpret_cast<float*>(&acc[size_t(r) * half]);
        const float* x = reinterpret_cast<const float*>(&in[size_t(r) * half]);
        const float* k = reinterpret_cast<const float*>(kv.data + size_t(kv.flip_rows ? (N - r) % N : r) * half);
#pragma omp simd
        for (int e = 0; e < half; ++e) {
            const float kr = k[2 * e], ki = sign * k[2 * e + 1];
            a[2 * e] += x[2 * e] * kr - x[2 * e + 1] * ki;
            a[2 * e + 1] += x[2 * e] * ki + x[2 * e + 1] * kr;
        }
    });
}

// acc_q += sum_p in_p K_{3p+q} for the three primaries p and channels q at once (kv: the first of
// an anchor's nine kernel spectra, the others after it, spec apart; in and acc: three spectra
// each, spec apart): each value of the inputs and of acc read once, not three times (these sums
// are bound by memory), and each acc value's three terms added in the same order as
// multiply_add's one primary at a time.
__attribute__((target_clones("avx2", "default"))) void multiply_add_primaries_row(const float* const* x,
                                                                                   const float* const* k, float* const* a,
                                                                                   int half, float sign) {
    for (int q = 0; q < 3; ++q) {
        float* aq = a[q];
        const float *x0 = x[0], *x1 = x[1], *x2 = x[2], *k0 = k[q], *k1 = k[3 + q], *k2 = k[6 + q];
#pragma omp simd
        for (int e = 0; e < half; ++e) {
            float re = aq[2 * e], im = aq[2 * e + 1];
            const float kr0 = k0[2 * e], ki0 = sign * k0[2 * e + 1];
            re += x0[2 * e] * kr0 - x0[2 * e + 1] * ki0;
            im += x0[2 * e] * ki0 + x0[2 * e + 1] * kr0;
            const float kr1 = k1[2 * e], ki1 = sign * k1[2 * e + 1];
            re += x1[2 * e] * kr1 - x1[2 * e + 1] * ki1;
            im += x1[2 * e] * ki1 + x1[2 * e + 1] * kr1;
            const float kr2 = k2[2 * e], ki2 = sign * k2[2 * e + 1];
            re += x2[2 * e] * kr2 - x2[2 * e + 1] * ki2;
            im += x2[2 * e] * ki2 + x2[2 * e + 1] * kr2;
            aq[2 * e] = re;
            aq[2 * e + 1] = im;
        }
    }
}

void multiply_add_primaries(const std::complex<float>* in, size_t spec, const AnchoredConvolution::KernelView& kv,
                            std::complex<float>* acc, int N, int half, int threads) {
    const float sign = kv.conjugate ? -1.0f : 1.0f;
    parallel_for(0, N, threads, [&](int64_t r) {
        const size_t row = size_t(r) * half, kernel_row = size_t(kv.flip_rows ? (N - r) % N : r) * half;
        const float *x[3], *k[9];
        float* a[3];
        for (int p = 0; p < 3; ++p) {
            x[p] = reinterpret_cast<const float*>(&in[p * spec + row]);
            a[p] = reinterpret_cast<float*>(&acc[p * spec + row]);
        }
        for (int m = 0; m < 9; ++m) k[m] = reinterpret_cast<const float*>(kv.data + m * spec + kernel_row);
        multiply_add_primaries_row(x, k, a, half, sign);
    });
}

// A tile's FFT frame: width x height, holding the tile's sources `bounds` and the R pixels its
// kernels spread beyond them (wrapped).
struct TileFrame {
    int width, height, radius;
    TileBounds bounds;
};

// Adds channel q of a tile's convolved image (its FFT frame, wrapped) to the output window.
void add_to_output(const float* image, const TileFrame& frame, const OutputWindow& out, float norm, int q,
                   float* xyz, int threads) {
    const int Nx = frame.width, Ny = frame.height, R = frame.radius;
    const TileBounds& b = frame.bounds;
    const int out_x0 = out.x0, out_y0 = out.y0, out_width = out.width, out_height = out.height;
    parallel_for(-R, (b.y1 - b.y0) + R, threads, [&](int64_t r64) {
        const int r = int(r64), j = b.y0 + r - out_y0;
        if (j < 0 || j >= out_height) return;
        for (int s = -R; s < (b.x1 - b.x0) + R; ++s) {
            const int i = b.x0 + s - out_x0;
            if (i < 0 || i >= out_width) continue;
            xyz[3 * (size_t(j) * out_width + i) + q] += norm * image[size_t((r + Ny) % Ny) * Nx + (s + Nx) % Nx];
        }
    });
}

}  // namespace

// A tile's working arrays, one set a thread or one that the threads share (shares_tile_scratch):
// its transform, the weighted image (the kernels' too, where the plan keeps no spectra), the
// input spectra (one; one per anchor of a group where the plan keeps no kernel spectra), the
// accumulated spectra, and one kernel's spectrum where the plan keeps none. Where the plan keeps
// spectra (tiles of a few hundred pixels), also the tile's light per primary, read once a tile
// rather than once per anchor and layer.
// (On huge pages where large, base/large_array.h: a whole-domain tile's arrays are tens of MB each.)
struct AnchoredConvolution::TileScratch {
    RealFft2D fft;
    LargeArray<float> image, weight, light;
    LargeArray<std::complex<float>> in, acc, own;
    int threads = 1;  // the threads each step is spread over (RealFft2D::set_threads): 1, or a whole-domain tile's
    TileScratch(int Nx, int Ny, size_t tile_pixels, size_t spec, int inputs, bool own_kernels)
        : fft(Nx, Ny),
          image(size_t(Nx) * Ny, Pages::huge_if_large),
          weight(tile_pixels, Pages::huge_if_large),
          light(own_kernels ? 0 : 3 * tile_pixels, Pages::huge_if_large),
          in(inputs * spec, Pages::huge_if_large),
          acc(3 * spec, Pages::huge_if_large),
          own(own_kernels ? spec : 0, Pages::huge_if_large) {}  // (zero until written)
};

// The tile's light, primary p's at [p T H, (p + 1) T H) row by row (T x H the tile's sides),
// where the scratch keeps it.
void keep_tile_light(const DomainSources& src, const TileBounds& b, float* light, int threads) {
    const int T = b.x1 - b.x0;
    const size_t plane = size_t(T) * (b.y1 - b.y0);
    parallel_for(b.y0, b.y1, threads, [&](int64_t j64) {
        const int j = int(j64);
        for (int i = b.x0; i < b.x1; ++i)
            for (int p = 0; p < 3; ++p) light[p * plane + size_t(j - b.y0) * T + (i - b.x0)] = src.light(i, j, p);
    });
}

// The anchors of one depth layer that share one computed anchor's kernels (it and its mirror
// images) and that a tile meets.
struct AnchoredConvolution::KernelGroup {
    int layer, source;
    std::vector<int> anchors;
};

std::vector<AnchoredConvolution::KernelGroup> AnchoredConvolution::groups_of(const DomainSources& src,
                                                                              const TileBounds& b) const {
    // the anchors whose hats reach into the tile: the knots of the cells it spans, at the depth
    // layers its sources touch
    const KernelTable& t = table_;
    const int kx0 = t.ax.cell_of(b.x0), kx1 = t.ax.cell_of(b.x1 - 1) + 1;
    const int ky0 = t.ay.cell_of(b.y0), ky1 = t.ay.cell_of(b.y1 - 1) + 1, nkx = int(t.ax.knots.size());
    int lo, hi;
    layer_span(src, b, t.layers.count, lo, hi);
    std::vector<KernelGroup> groups;
    for (int l = lo; l <= hi; ++l)
        for (int ky = ky0; ky <= ky1; ++ky)
            for (int kx = kx0; kx <= kx1; ++kx) {
                const int anchor = ky * nkx + kx, source = t.source[anchor];
                auto g = std::find_if(groups.begin(), groups.end(),
                                      [&](const KernelGroup& k) { return k.layer == l && k.source == source; });
                if (g == groups.end()) g = groups.insert(groups.end(), KernelGroup{l, source, {}});
                g->anchors.push_back(anchor);
            }
    return groups;
}

void AnchoredConvolution::light_spectrum(const DomainSources& src, const TileBounds& b, int first, int last, int p,
                                         TileScratch& s, std::complex<float>* in) const {
    const int Nx = fft_width_, T = b.x1 - b.x0;
    const float* kept = s.light.size() ? &s.light[p * size_t(T) * (b.y1 - b.y0)] : nullptr;
    parallel_for(b.y0, b.y1, s.threads, [&](int64_t j64) {
        const int j = int(j64);
        const size_t row = size_t(j - b.y0) * T;
        float* image = &s.image[size_t(j - b.y0) * Nx];
        if (kept) {
            for (int i = 0; i < T; ++i) image[i] = s.weight[row + i] == 0.0f ? 0.0f : s.weight[row + i] * kept[row + i];
            return;
        }
        for (int i = b.x0; i < b.x1; ++i) {
            const float w = s.weight[row + (i - b.x0)];
            image[i - b.x0] = w == 0.0f ? 0.0f : w * src.light(i, j, p);
        }
    });
    s.fft.forward(s.image.data(), in, first, last);
}

void AnchoredConvolution::add_group(const DomainSources& src, const TileBounds& b, const KernelGroup& g,
                                    TileScratch& s) const {
    const KernelTable& t = table_;
    const int Nx = fft_width_, half = fft_height_ / 2 + 1, nkx = int(t.ax.knots.size());
    const size_t spec = spectrum_size_;
    auto weights = [&](int anchor) {
        return anchor_weights(t, src, b, {g.layer, anchor % nkx, anchor / nkx}, s.weight.data(), s.threads);
    };
    if (!kernel_spectra_.empty()) {  // the plan's spectra: each anchor in turn
        for (const int anchor : g.anchors) {
            const LitColumns lit = weights(anchor);
            if (lit.first >= lit.last) continue;
            for (int p = 0; p < 3; ++p) light_spectrum(src, b, lit.first, lit.last, p, s, &s.in[p * spec]);
            multiply_add_primaries(s.in.data(), spec, spectrum(g.layer, anchor, 0), s.acc.data(), Nx, half, s.threads);
        }
        return;
    }
    // None kept: a primary's light of every anchor of the group transformed, then each kernel
    // that takes that primary transformed once and applied to them all (read mirrored for a
    // mirror image): a kernel's spectrum and one per anchor held, not the group's nine. The
    // weights are found again for each primary: one array of them, not one per anchor.
    for (int p = 0; p < 3; ++p) {
        std::vector<int> lit_anchors;
        for (const int anchor : g.anchors) {
            const LitColumns lit = weights(anchor);
            if (lit.first >= lit.last) continue;
            light_spectrum(src, b, lit.first, lit.last, p, s, &s.in[lit_anchors.size() * spec]);
            lit_anchors.push_back(anchor);
        }
        if (lit_anchors.empty()) return;
        parallel_for(0, b.y1 - b.y0, s.threads, [&](int64_t j) {  // the kernels go through the image: zero but for the tile
            std::fill_n(&s.image[size_t(j) * Nx], b.x1 - b.x0, 0.0f);
        });
        for (int q = 0; q < 3; ++q) {
            transform_kernel(t.kernel_index(g.layer, g.source, 3 * p + q), s.fft, s.image.data(), s.own.data(), s.threads);
            for (size_t k = 0; k < lit_anchors.size(); ++k) {
                const bool in_x = t.mirrored_x(lit_anchors[k]), in_y = t.mirrored_y(lit_anchors[k]);
                multiply_add(&s.in[k * spec], {s.own.data(), in_x != in_y, in_y}, &s.acc[q * spec], Nx, half, s.threads);
            }
        }
    }
}

void AnchoredConvolution::add_tile_light(const TileBounds& b, std::complex<float>* acc, int q, const OutputWindow& out,
                                         float* xyz, TileScratch& s) const {
    const int Nx = fft_width_, Ny = fft_height_;
    s.fft.inverse(&acc[q * spectrum_size_], s.image.data());
    const float norm = 1.0f / (float(Nx) * Ny);  // the transforms leave the inverse unnormalised
    add_to_output(s.image.data(), {Nx, Ny, table_.radius, b}, out, norm, q, xyz, s.threads);
}

Result<bool> AnchoredConvolution::apply(const DomainSources& src, const OutputWindow& out, float* xyz,
                                        const ProgressFn& progress) const {
    const int Nx = fft_width_, Ny = fft_height_, R = table_.radius;
    const int ntx = int(edges_x_.size()) - 1, nty = int(edges_y_.size()) - 1;
    const size_t spec = spectrum_size_;
    const bool own_kernels = kernel_spectra_.empty();
    int widest = 0, tallest = 0;  // the largest tile's sides (a whole-domain tile's are the domain's)
    for (int k = 0; k < ntx; ++k) widest = std::max(widest, edges_x_[k + 1] - edges_x_[k]);
    for (int k = 0; k < nty; ++k) tallest = std::max(tallest, edges_y_[k + 1] - edges_y_[k]);
    const size_t tile_pixels = size_t(widest) * tallest;
    // input spectra: the three primaries', or, where each group's kernels are transformed, one per
    // anchor of the largest group
    int inputs = own_kernels ? 1 : 3;
    for (int a = 0; a < table_.anchors() && own_kernels; ++a)
        inputs = std::max<int>(inputs, std::count(table_.source.begin(), table_.source.end(), table_.source[a]));
    ProgressTicker ticker(progress, double(ntx) * nty);
    // Passes of tiles px apart across and py down (pass_period): a tile writes at most R pixels
    // beyond itself and the tiles between two of one pass span 2 R, so concurrent tiles never
    // write the same pixel (tiles of 2 R or more: four passes).
    const int px = pass_period(edges_x_, R), py = pass_period(edges_y_, R);
    for (int phase = 0; phase < px * py && !ticker.cancelled(); ++phase) {
        std::vector<TileBounds> tiles;
        for (int ty = phase / px; ty < nty; ty += py)
            for (int tx = phase % px; tx < ntx; tx += px) {
                const TileBounds b{edges_x_[tx], edges_y_[ty], edges_x_[tx + 1], edges_y_[ty + 1]};
                if (b.x1 + R <= out.x0 || b.x0 - R >= out.x0 + out.width || b.y1 + R <= out.y0 ||
                    b.y0 - R >= out.y0 + out.height)
                    ticker.advance(1, true);  // its light cannot reach the output window
                else
                    tiles.push_back(b);
            }
        if (int(tiles.size()) >= nthreads_) {  // a tile a thread
            parallel_team(nthreads_, [&](Team& team) {
                TileScratch s(Nx, Ny, tile_pixels, spec, inputs, own_kernels);
                team.for_dynamic(0, int64_t(tiles.size()), 1, [&](int64_t k) {
                    if (ticker.cancelled()) return;
                    const std::vector<KernelGroup> groups = groups_of(src, tiles[k]);
                    std::fill_n(s.acc.data(), s.acc.size(), std::complex<float>(0));
                    std::fill_n(s.image.data(), s.image.size(), 0.0f);  // (the last tile's inverse)
                    if (s.light.size()) keep_tile_light(src, tiles[k], s.light.data(), s.threads);
                    for (const KernelGroup& g : groups) add_group(src, tiles[k], g, s);
                    for (int q = 0; q < 3 && !groups.empty(); ++q) add_tile_light(tiles[k], s.acc.data(), q, out, xyz, s);
                    ticker.advance(1, team.rank() == 0);
                });
            });
            continue;
        }
        // Fewer tiles than threads (kernels wide against the frame: one whole-domain tile).
        const bool shared = shares_tile_scratch(double(tiles.size()), nthreads_,
                                                tile_scratch_bytes(double(Nx) * Ny, double(tile_pixels), double(spec),
                                                                   inputs, own_kernels),
                                                tile_memory_);
        for (const TileBounds& b : tiles) {
            const std::vector<KernelGroup> groups = groups_of(src, b);
            if (shared) {  // one set of arrays, each step of each kernel group spread over the threads
                TileScratch s(Nx, Ny, tile_pixels, spec, inputs, own_kernels);
                s.threads = nthreads_;
                s.fft.set_threads(nthreads_);
                if (s.light.size()) keep_tile_light(src, b, s.light.data(), s.threads);
                for (const KernelGroup& g : groups)
                    if (!ticker.cancelled()) add_group(src, b, g, s);
                for (int q = 0; q < 3 && !groups.empty() && !ticker.cancelled(); ++q)
                    add_tile_light(b, s.acc.data(), q, out, xyz, s);
                ticker.advance(1, true);
                continue;
            }
            // A set each: the kernel groups spread over the threads in turn (the same groups to
            // the same thread every run), their sums added in the threads' order into the first
            // thread's, the three channels' inverse transforms spread too: the same image every run.
            std::vector<TileScratch*> scratch(nthreads_, nullptr);
            parallel_team(nthreads_, [&](Team& team) {
                TileScratch s(Nx, Ny, tile_pixels, spec, inputs, own_kernels);
                const int threads = team.size();
                scratch[size_t(team.rank())] = &s;
                if (s.light.size()) keep_tile_light(src, b, s.light.data(), 1);
                team.for_strided(0, int64_t(groups.size()), 1, [&](int64_t k) {
                    if (!ticker.cancelled()) add_group(src, b, groups[k], s);
                });
                std::complex<float>* acc = scratch[0]->acc.data();
                team.for_blocks(0, int64_t(3 * spec), [&](int64_t e) {
                    for (int other = 1; other < threads; ++other) acc[e] += scratch[other]->acc[e];
                });
                team.for_strided(0, 3, 1, [&](int64_t q) {
                    if (!groups.empty()) add_tile_light(b, acc, int(q), out, xyz, s);
                });
            });
            ticker.advance(1, true);
        }
    }
    if (ticker.cancelled()) return Result<bool>::failure("cancelled", ErrorKind::Cancelled);
    return Result<bool>::success(true);
}

}  // namespace wavecam::detail
