#include "fft/real_fft2d.h"

#include <algorithm>
#include <cstring>

#include "base/parallel.h"

namespace wavecam::detail {
namespace {

// Pairs of columns unpacked (forward) or packed (inverse) together: eight complex values, one
// cache line of a row.
constexpr int kPairBlock = 8;

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
    // 2. each column's transform, rows ky = 0 .. height/2, written straight into the spectrum's
    // transposed layout: a block of pairs at a time, so that its reads (a few cache lines of two
    // rows) and its writes (its columns' spectrum rows, in order) stay in cache
    parallel_for(0, (pairs_ + kPairBlock - 1) / kPairBlock, T, [&](int64_t block) {
        const int c0 = int(block) * kPairBlock, c1 = std::min(pairs_, c0 + kPairBlock);
        for (int ky = 0; ky < half_; ++ky) {
            const std::complex<float>* z = &packed_[size_t(ky) * pairs_];
            const std::complex<float>* zm = &packed_[size_t((h_ - ky) % h_) * pairs_];
            for (int c = c0; c < c1; ++c) {
                const float ar = z[c].real(), ai = z[c].imag(), br = zm[c].real(), bi = -zm[c].imag();
                // E = (a + b) / 2 (column 2c), O = (a - b) / 2i (column 2c + 1), b = conj Z[-ky]
                spectrum[size_t(2 * c) * half_ + ky] = {0.5f * (ar + br), 0.5f * (ai + bi)};
                spectrum[size_t(2 * c + 1) * half_ + ky] = {0.5f * (ai - bi), -0.5f * (ar - br)};
            }
        }
    });
    // 3. across: the transposed rows' columns
    row_forward_.transform(spectrum, work_.data(), half_, 0, half_, T);
}

void RealFft2D::inverse(std::complex<float>* spectrum, float* image) {
    const int T = threads_;
    row_inverse_.transform(spectrum, work_.data(), half_, 0, half_, T);
    // the column pairs, the negative ky rows as conjugates: z = E + i O, read from the spectrum's
    // transposed layout a block of pairs at a time (as forward's step 2)
    std::complex<float>* packed = reinterpret_cast<std::complex<float>*>(image);
    parallel_for(0, (pairs_ + kPairBlock - 1) / kPairBlock, T, [&](int64_t block) {
        const int c0 = int(block) * kPairBlock, c1 = std::min(pairs_, c0 + kPairBlock);
        for (int ky = 0; ky < h_; ++ky) {
            const bool mirrored = ky >= half_;
            const int row = mirrored ? h_ - ky : ky;
            const float sign = mirrored ? -1.0f : 1.0f;  // conjugated
            std::complex<float>* out = &packed[size_t(ky) * pairs_];
            for (int c = c0; c < c1; ++c) {
                const std::complex<float> e = spectrum[size_t(2 * c) * half_ + row], o = spectrum[size_t(2 * c + 1) * half_ + row];
                const float er = e.real(), ei = sign * e.imag(), orr = o.real(), oi = sign * o.imag();
                out[c] = {er - oi, ei + orr};
            }
        }
    });
    column_inverse_.transform(packed, work_.data(), pairs_, 0, pairs_, T);
}

}  // namespace wavecam::detail
