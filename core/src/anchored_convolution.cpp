#include "anchored_convolution.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <memory>

#include "progress_ticker.h"
#include "real_fft2d.h"

namespace wavecam::detail {

int convolution_fft_size(int tile, int radius, int width, int height) {
    return fft_friendly_size(tile >= std::max(width, height) ? std::max(width, height) : tile + 2 * radius);
}

Result<AnchoredConvolution> AnchoredConvolution::create(PsfTable table, int tile, int width, int height, int nthreads,
                                                        const ProgressFn& progress) {
    AnchoredConvolution c;
    const int R = table.radius, kw = 2 * R + 1;
    c.tile_ = tile;
    c.fft_size_ = convolution_fft_size(tile, R, width, height);
    c.nthreads_ = nthreads;
    c.table_ = std::move(table);
    const PsfTable& t = c.table_;
    const int N = c.fft_size_;
    const long count = long(t.layers.count) * t.anchors() * 9;
    std::vector<std::unique_ptr<RealFft2D>> ffts(nthreads);
    {
        RealFft2D probe(N);
        if (!probe.ok())
            return Result<AnchoredConvolution>::failure("fft: cannot set up a " + std::to_string(N) + "-point transform");
        c.spectrum_size_ = probe.spectrum_size();
    }
    c.kernel_spectra_.resize(size_t(count) * c.spectrum_size_);
    ProgressTicker ticker(progress, double(count));
#pragma omp parallel num_threads(nthreads)
    {
        RealFft2D fft(N);
        std::vector<float> image(size_t(N) * N, 0.0f);
#pragma omp for schedule(dynamic, 4)
        for (long k = 0; k < count; ++k) {
            if (ticker.cancelled()) continue;
            const float* w = &t.weights[size_t(k) * t.kernel_size()];
            // the kernel centred on the origin, wrapped
            for (int b = -R; b <= R; ++b)
                for (int a = -R; a <= R; ++a)
                    image[size_t((b + N) % N) * N + (a + N) % N] = w[size_t(b + R) * kw + (a + R)];
            fft.forward(image.data(), &c.kernel_spectra_[size_t(k) * c.spectrum_size_], R + 1, N - R);
            for (int b = -R; b <= R; ++b)
                for (int a = -R; a <= R; ++a) image[size_t((b + N) % N) * N + (a + N) % N] = 0.0f;
            ticker.advance(1, omp_get_thread_num() == 0);
        }
    }
    if (ticker.cancelled()) return Result<AnchoredConvolution>::failure("cancelled", ErrorKind::Cancelled);
    return Result<AnchoredConvolution>::success(std::move(c));
}

Result<bool> AnchoredConvolution::apply(const DomainSources& src, int out_x0, int out_y0, int out_width,
                                        int out_height, float* xyz, const ProgressFn& progress) const {
    const PsfTable& t = table_;
    const int T = tile_, N = fft_size_, R = t.radius, W = src.width, H = src.height;
    const int ntx = (W + T - 1) / T, nty = (H + T - 1) / T, nkx = int(t.ax.knots.size());
    const size_t spec = spectrum_size_;
    const float norm = 1.0f / (float(N) * N);  // kissfft leaves the inverse unnormalised
    ProgressTicker ticker(progress, double(ntx) * nty);
    // Four passes: tiles of one parity are at least one tile apart, and a tile writes at most
    // R <= T/2 pixels beyond itself, so concurrent tiles never write the same pixel.
    for (int phase = 0; phase < 4; ++phase) {
#pragma omp parallel num_threads(nthreads_)
        {
            RealFft2D fft(N);
            // image: the tile in its top-left corner, zero elsewhere (the FFT's padding)
            std::vector<float> image(size_t(N) * N), weight(size_t(T) * T);
            std::vector<std::complex<float>> in(3 * spec), acc(3 * spec);
#pragma omp for schedule(dynamic, 1)
            for (long k = 0; k < long(ntx) * nty; ++k) {
                const int tx = int(k % ntx), ty = int(k / ntx);
                if ((tx % 2) + 2 * (ty % 2) != phase || ticker.cancelled()) continue;
                const int x0 = tx * T, y0 = ty * T, x1 = std::min(W, x0 + T), y1 = std::min(H, y0 + T);
                // skip tiles whose light cannot reach the output window
                if (x1 + R <= out_x0 || x0 - R >= out_x0 + out_width || y1 + R <= out_y0 ||
                    y0 - R >= out_y0 + out_height) {
                    ticker.advance(1, omp_get_thread_num() == 0);
                    continue;
                }
                const int cx = t.ax.cell_of(x0), cy = t.ay.cell_of(y0);
                int lo = t.layers.count, hi = -1;
                for (int j = y0; j < y1; ++j)
                    for (int i = x0; i < x1; ++i) {
                        const size_t p = size_t(j) * W + i;
                        lo = std::min<int>(lo, src.lower[p]);
                        hi = std::max<int>(hi, src.lower[p] + (src.upper_share[p] > 0 ? 1 : 0));
                    }
                std::fill(acc.begin(), acc.end(), std::complex<float>(0));
                std::fill(image.begin(), image.end(), 0.0f);
                for (int l = lo; l <= hi; ++l)
                    for (int corner = 0; corner < 4; ++corner) {
                        const int dx = corner & 1, dy = corner >> 1;
                        const int anchor = (cy + dy) * nkx + (cx + dx);
                        // this anchor's and layer's share of each source
                        bool any = false;
                        for (int j = y0; j < y1; ++j) {
                            const double by = t.ay.upper_weight(cy, j);
                            const float wy = float(dy ? by : 1 - by);
                            for (int i = x0; i < x1; ++i) {
                                const size_t q = size_t(j) * W + i;
                                const float share = src.lower[q] == l         ? 1.0f - src.upper_share[q]
                                                    : src.lower[q] + 1 == l ? src.upper_share[q]
                                                                            : 0.0f;
                                const double bx = t.ax.upper_weight(cx, i);
                                const float w = share * wy * float(dx ? bx : 1 - bx);
                                weight[size_t(j - y0) * T + (i - x0)] = w;
                                any |= w > 0;
                            }
                        }
                        if (!any) continue;
                        for (int p = 0; p < 3; ++p) {
                            for (int j = y0; j < y1; ++j)
                                for (int i = x0; i < x1; ++i)
                                    image[size_t(j - y0) * N + (i - x0)] =
                                        weight[size_t(j - y0) * T + (i - x0)] * src.rgb[3 * (size_t(j) * W + i) + p];
                            fft.forward(image.data(), &in[p * spec], y1 - y0, N);
                        }
                        // acc_q += sum_p in_p K_{3p+q}, written on floats so that it vectorises
                        // (std::complex's operator* keeps a NaN-recovery branch)
                        for (int q = 0; q < 3; ++q) {
                            float* a = reinterpret_cast<float*>(&acc[q * spec]);
                            for (int p = 0; p < 3; ++p) {
                                const float* x = reinterpret_cast<const float*>(&in[p * spec]);
                                const float* k = reinterpret_cast<const float*>(spectrum(l, anchor, 3 * p + q));
#pragma omp simd
                                for (size_t e = 0; e < spec; ++e) {
                                    a[2 * e] += x[2 * e] * k[2 * e] - x[2 * e + 1] * k[2 * e + 1];
                                    a[2 * e + 1] += x[2 * e] * k[2 * e + 1] + x[2 * e + 1] * k[2 * e];
                                }
                            }
                        }
                    }
                if (hi >= lo)
                    for (int q = 0; q < 3; ++q) {
                        fft.inverse(&acc[q * spec], image.data());
                        for (int r = -R; r < (y1 - y0) + R; ++r) {
                            const int j = y0 + r - out_y0;
                            if (j < 0 || j >= out_height) continue;
                            for (int s = -R; s < (x1 - x0) + R; ++s) {
                                const int i = x0 + s - out_x0;
                                if (i < 0 || i >= out_width) continue;
                                xyz[3 * (size_t(j) * out_width + i) + q] +=
                                    norm * image[size_t((r + N) % N) * N + (s + N) % N];
                            }
                        }
                    }
                ticker.advance(1, omp_get_thread_num() == 0);
            }
        }
    }
    if (ticker.cancelled()) return Result<bool>::failure("cancelled", ErrorKind::Cancelled);
    return Result<bool>::success(true);
}

}  // namespace wavecam::detail
