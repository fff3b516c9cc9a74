#include "fft/real_fft2d.h"

#include <algorithm>

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
    // 1. column pairs, read from the image by the first stage (rows of width floats are rows of
    // width/2 packed pairs): the result in packed_ or work_; packed c is zero where both its
    // columns are, and its transform skipped
    const int T = threads_;
    const std::complex<float>* pairs = reinterpret_cast<const std::complex<float>*>(image);
    if (last < 0) last = w_;
    const int p0 = std::max(0, first) / 2, count = std::min(pairs_, (last + 1) / 2 - p0);
    const int a = ((p0 % pairs_) + pairs_) % pairs_;
    // (the pairs transformed: [a, a + count) modulo pairs_)
    auto transformed = [&](int c) { return count > 0 && (c - a + pairs_) % pairs_ < count; };
    const std::complex<float>* z_all = column_forward_.ends_in_work() ? work_.data() : packed_.data();
    if (count > 0) {
        column_forward_.transform_where(packed_.data(), work_.data(), pairs_, a, std::min(pairs_, a + count), T, pairs);
        if (a + count > pairs_)
            column_forward_.transform_where(packed_.data(), work_.data(), pairs_, 0, a + count - pairs_, T, pairs);
    }
    // 2. each column's transform, rows ky = 0 .. height/2, written straight into the transposed
    // layout: a block of pairs at a time, so that its reads (a few cache lines of two rows) and
    // its writes (its columns' spectrum rows, in order) stay in cache. Written to the array from
    // which step 3's last stage lands in the spectrum: the spectrum, or work_ (an odd number of
    // stages), where step 1's result is no longer needed once read.
    std::complex<float>* across = row_forward_.ends_in_work() ? work_.data() : spectrum;
    if (across == z_all) {  // (step 1's result in work_ too: moved to packed_ first, which step 1 left free)
        for (int r = 0; r < h_; ++r)
            std::copy_n(&work_[size_t(r) * pairs_], pairs_, &packed_[size_t(r) * pairs_]);
        z_all = packed_.data();
    }
    parallel_for(0, (pairs_ + kPairBlock - 1) / kPairBlock, T, [&](int64_t block) {
        const int c0 = int(block) * kPairBlock, c1 = std::min(pairs_, c0 + kPairBlock);
        for (int ky = 0; ky < half_; ++ky) {
            const std::complex<float>* z = &z_all[size_t(ky) * pairs_];
            const std::complex<float>* zm = &z_all[size_t((h_ - ky) % h_) * pairs_];
            for (int c = c0; c < c1; ++c) {
                if (!transformed(c)) {  // (both columns zero)
                    across[size_t(2 * c) * half_ + ky] = across[size_t(2 * c + 1) * half_ + ky] = 0.0f;
                    continue;
                }
                const float ar = z[c].real(), ai = z[c].imag(), br = zm[c].real(), bi = -zm[c].imag();
                // E = (a + b) / 2 (column 2c), O = (a - b) / 2i (column 2c + 1), b = conj Z[-ky]
                across[size_t(2 * c) * half_ + ky] = {0.5f * (ar + br), 0.5f * (ai + bi)};
                across[size_t(2 * c + 1) * half_ + ky] = {0.5f * (ai - bi), -0.5f * (ar - br)};
            }
        }
    });
    // 3. across: the transposed rows' columns, landing in the spectrum
    row_forward_.transform_where(across, across == spectrum ? work_.data() : spectrum, half_, 0, half_, T);
}

void RealFft2D::inverse(std::complex<float>* spectrum, float* image) {
    const int T = threads_;
    // the rows' result in the spectrum or in work_; the other array is free for the columns
    const std::complex<float>* rows = row_inverse_.transform_where(spectrum, work_.data(), half_, 0, half_, T);
    std::complex<float>* free = rows == spectrum ? work_.data() : spectrum;
    // the column pairs, the negative ky rows as conjugates: z = E + i O, read from the transposed
    // layout a block of pairs at a time (as forward's step 2), written where the columns' last
    // stage then lands in the image (two columns a value): the image, or the free array (an odd
    // number of stages; the spectrum is larger than the packed pairs)
    std::complex<float>* image_pairs = reinterpret_cast<std::complex<float>*>(image);
    std::complex<float>* packed = column_inverse_.ends_in_work() ? free : image_pairs;
    parallel_for(0, (pairs_ + kPairBlock - 1) / kPairBlock, T, [&](int64_t block) {
        const int c0 = int(block) * kPairBlock, c1 = std::min(pairs_, c0 + kPairBlock);
        for (int ky = 0; ky < h_; ++ky) {
            const bool mirrored = ky >= half_;
            const int row = mirrored ? h_ - ky : ky;
            const float sign = mirrored ? -1.0f : 1.0f;  // conjugated
            std::complex<float>* out = &packed[size_t(ky) * pairs_];
            for (int c = c0; c < c1; ++c) {
                const std::complex<float> e = rows[size_t(2 * c) * half_ + row];
                const std::complex<float> o = rows[size_t(2 * c + 1) * half_ + row];
                const float er = e.real(), ei = sign * e.imag(), orr = o.real(), oi = sign * o.imag();
                out[c] = {er - oi, ei + orr};
            }
        }
    });
    column_inverse_.transform_where(packed, packed == image_pairs ? free : image_pairs, pairs_, 0, pairs_, T);
}

}  // namespace wavecam::detail
