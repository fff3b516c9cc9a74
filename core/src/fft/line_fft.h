// Complex 1D FFTs of many lines of one length, each transformed in place, through the column
// transforms (column_fft.h): the lines gathered as the columns of one array, so that every
// butterfly runs across all of them at once, then put back. Lines may lie anywhere (rows of a
// grid, a list of them). Unnormalised in both directions. Internal to core; one object per
// thread.
#pragma once
#include <algorithm>
#include <complex>
#include <vector>

#include "fft/column_fft.h"

namespace wavecam::detail {

class LineFft {
public:
    LineFft(int length, bool inverse) : fft_(length, inverse) {}

    bool ok() const { return fft_.ok(); }
    int length() const { return fft_.length(); }

    // Transforms `count` lines in place: line k starts at line_at(k).
    template <class LineAt>
    void transform(int count, LineAt line_at) {
        const int n = fft_.length();
        if (count <= 0) return;
        columns_.resize(size_t(n) * count);
        work_.resize(size_t(n) * count);
        // lines gathered a block at a time, each value of the block's lines in turn: the block's
        // reads run along its lines and its writes fill a cache line of the columns at a time
        constexpr int kBlock = 16;
        const std::complex<float>* in[kBlock];
        std::complex<float>* out[kBlock];
        for (int k0 = 0; k0 < count; k0 += kBlock) {
            const int k1 = std::min(count, k0 + kBlock);
            for (int k = k0; k < k1; ++k) in[k - k0] = line_at(k);
            for (int i = 0; i < n; ++i)
                for (int k = k0; k < k1; ++k) columns_[size_t(i) * count + k] = in[k - k0][i];
        }
        fft_.transform(columns_.data(), work_.data(), count, 0, count);
        for (int k0 = 0; k0 < count; k0 += kBlock) {
            const int k1 = std::min(count, k0 + kBlock);
            for (int k = k0; k < k1; ++k) out[k - k0] = line_at(k);
            for (int i = 0; i < n; ++i)
                for (int k = k0; k < k1; ++k) out[k - k0][i] = columns_[size_t(i) * count + k];
        }
    }

private:
    ColumnFft fft_;
    std::vector<std::complex<float>> columns_, work_;
};

}  // namespace wavecam::detail
