// Complex 2D FFTs of one rectangular size: the columns transformed every one at once
// (column_fft.h), the rows as the columns of the transposed array. Transforms of fewer than
// kParallelPoints points run on the calling thread (callers run several at once); larger ones
// spread their columns and transposes over the threads. Internal to core.
#pragma once
#include <complex>

#include "fft/column_fft.h"

namespace wavecam::detail {

class ComplexFft2D {
public:
    ComplexFft2D(int width, int height, int nthreads)
        : w_(width),
          h_(height),
          threads_(nthreads),
          row_forward_(width, false),
          row_inverse_(width, true),
          column_forward_(height, false),
          column_inverse_(height, true) {}

    bool ok() const { return row_forward_.ok() && row_inverse_.ok() && column_forward_.ok() && column_inverse_.ok(); }
    int width() const { return w_; }
    int height() const { return h_; }
    size_t size() const { return size_t(w_) * h_; }

    // In place, height x width row-major. Rows at or beyond `rows` are known to be zero (their
    // transforms are skipped). Neither direction is normalised: inverse(forward(x)) = size() x.
    void forward(std::complex<float>* data, int rows = -1) const;
    void inverse(std::complex<float>* data) const;

    // Transforms of fewer points run on one thread.
    static constexpr size_t kParallelPoints = 1 << 16;

private:
    void transform(std::complex<float>* data, int rows, const ColumnFft& row, const ColumnFft& column) const;

    int w_, h_, threads_;
    ColumnFft row_forward_, row_inverse_, column_forward_, column_inverse_;
};

}  // namespace wavecam::detail
