#include "fft/real_fft2d.h"

#include <algorithm>
#include <cstring>

#include "base/parallel.h"

namespace wavecam::detail {
namespace {

// dst (columns x rows) = the transpose of src (rows x columns), in tiles that stay in cache.
void transpose(const std::complex<float>* src, std::complex<float>* dst, int rows, int columns, int threads) {
    constexpr int kTile = 32;
    parallel_for(0, (rows + kTile - 1) / kTile, threads, [&](int64_t tile) {
        const int r0 = int(tile) * kTile;
        for (int c0 = 0; c0 < columns; c0 += kTile) {
            const int r1 = std::min(r0 + kTile, rows), c1 = std::min(c0 + kTile, columns);
            for (int r = r0; r < r1; ++r)
                for (int c = c0; c < c1; ++c) dst[size_t(c) * rows + r] = src[size_t(r) * columns + c];
        }
    });
}

}  // namespace

RealFft2D::RealFft2D(int width, int height)
    : w_(width),
      h_(height),
      pairs_(width / 2),
      half_(height / 2 + 1),
      ok_(width >= 2 && width % 2 == 0 && height >= 1),
      column_forward_(height, false),
      column_inverse_(height, true),
      row_forward_(width, false),
      row_inverse_(width, true),
      packed_(size_t(height) * (width / 2), Pages::huge_if_large),
      rows_(size_t(height / 2 + 1) * width, Pages::huge_if_large),
      work_(std::max(size_t(height) * (width / 2), size_t(width) * (height / 2 + 1)), Pages::huge_if_large) {
    ok_ = ok_ && column_forward_.ok() && column_inverse_.ok() && row_forward_.ok() && row_inverse_.ok();
}

void RealFft2D::forward(const float* image, std::complex<float>* spectrum, int first, int last) {
    // 1. column pairs: packed c is zero where both its columns are
    const int T = threads_;
    parallel_for(0, h_, T, [&](int64_t y_) {
        const int y = int(y_);
        std::memcpy(static_cast<void*>(&packed_[size_t(y) * pairs_]), image + size_t(y) * w_, sizeof(float) * w_);
    });
    if (last < 0) last = w_;
    const int p0 = std::max(0, first) / 2, count = std::min(pairs_, (last + 1) / 2 - p0);
    if (count > 0) {
        const int a = ((p0 % pairs_) + pairs_) % pairs_;
        column_forward_.transform(packed_.data(), work_.data(), pairs_, a, std::min(pairs_, a + count), T);
        if (a + count > pairs_)
            column_forward_.transform(packed_.data(), work_.data(), pairs_, 0, a + count - pairs_, T);
    }
    // 2. each column's transform, rows ky = 0 .. height/2
    parallel_for(0, half_, T, [&](int64_t ky_) {
        const int ky = int(ky_);
        const std::complex<float>* z = &packed_[size_t(ky) * pairs_];
        const std::complex<float>* zm = &packed_[size_t((h_ - ky) % h_) * pairs_];
        float* out = reinterpret_cast<float*>(&rows_[size_t(ky) * w_]);
#pragma omp simd
        for (int c = 0; c < pairs_; ++c) {
            const float ar = z[c].real(), ai = z[c].imag(), br = zm[c].real(), bi = -zm[c].imag();
            out[4 * c] = 0.5f * (ar + br);  // E = (a + b) / 2, b = conj Z[-ky]
            out[4 * c + 1] = 0.5f * (ai + bi);
            out[4 * c + 2] = 0.5f * (ai - bi);  // O = (a - b) / 2i
            out[4 * c + 3] = -0.5f * (ar - br);
        }
    });
    // 3. across: the transposed rows' columns
    transpose(rows_.data(), spectrum, half_, w_, T);
    row_forward_.transform(spectrum, work_.data(), half_, 0, half_, T);
}

void RealFft2D::inverse(std::complex<float>* spectrum, float* image) {
    const int T = threads_;
    row_inverse_.transform(spectrum, work_.data(), half_, 0, half_, T);
    transpose(spectrum, rows_.data(), w_, half_, T);
    // the column pairs, the negative ky rows as conjugates: z = E + i O
    std::complex<float>* packed = reinterpret_cast<std::complex<float>*>(image);
    parallel_for(0, h_, T, [&](int64_t ky_) {
        const int ky = int(ky_);
        const bool mirrored = ky >= half_;
        const float* in = reinterpret_cast<const float*>(&rows_[size_t(mirrored ? h_ - ky : ky) * w_]);
        const float sign = mirrored ? -1.0f : 1.0f;  // conjugated
        float* out = reinterpret_cast<float*>(&packed[size_t(ky) * pairs_]);
#pragma omp simd
        for (int c = 0; c < pairs_; ++c) {
            const float er = in[4 * c], ei = sign * in[4 * c + 1], orr = in[4 * c + 2], oi = sign * in[4 * c + 3];
            out[2 * c] = er - oi;
            out[2 * c + 1] = ei + orr;
        }
    });
    column_inverse_.transform(packed, work_.data(), pairs_, 0, pairs_, T);
}

}  // namespace wavecam::detail
