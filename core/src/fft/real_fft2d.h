// Real 2D FFTs of one size (width x height, width even) through the vectorised column transforms
// (column_fft.h), the one FFT of core. Internal to core; one object per thread, or one object
// whose every step is spread over `threads` of its own (set_threads: a transform too large to
// hold one per thread, a whole frame's tile), each thread its own columns or rows.
//
// Forward, for a real image x[y][x] (height rows of width):
//   1. pairs of columns packed as one complex column, z[y][c] = x[y][2c] + i x[y][2c+1], and
//      the height-point transforms of all width/2 of them at once: Z[ky][c];
//   2. each column's own transform from the pair's, by the symmetry of a real column's
//      spectrum, X(-ky) = conj X(ky):
//        E = (Z[ky] + conj Z[-ky]) / 2 (column 2c),  O = (Z[ky] - conj Z[-ky]) / 2i (column 2c+1),
//      for ky = 0 .. height/2 only (the rest is the conjugate);
//   3. the width-point transforms across those height/2 + 1 rows (columns of their transpose).
// The spectrum is kept transposed, S[kx][ky] for kx = 0 .. width-1 and ky = 0 .. height/2, so
// that no step transposes back: width rows of height/2 + 1 values. The inverse runs the steps
// backwards, the negative ky rows rebuilt as conjugates (a product of real images' spectra is
// a real image's), and the result lands packed, two columns a value, in the output image.
#pragma once
#include <complex>
#include <vector>

#include "base/large_array.h"
#include "fft/column_fft.h"

namespace wavecam::detail {

class RealFft2D {
public:
    RealFft2D(int width, int height);

    bool ok() const { return ok_; }
    // The spectrum's shape: rows kx = 0 .. width-1, columns ky = 0 .. height/2.
    int spectrum_rows() const { return w_; }
    int spectrum_columns() const { return half_; }
    size_t spectrum_size() const { return size_t(w_) * half_; }

    // height x width real (row-major) -> the spectrum. Columns outside [first, last), taken
    // modulo width (a wrapped kernel's range runs past the last column), are known to be zero (a
    // tile's padding, the columns an anchor's hat leaves dark): their transforms are skipped.
    void forward(const float* image, std::complex<float>* spectrum, int first = 0, int last = -1);
    // spectrum -> height x width real, scaled by width x height (neither direction normalises);
    // the spectrum is overwritten.
    void inverse(std::complex<float>* spectrum, float* image);
    // Each step spread over n threads (called from outside any parallel region); 1: the caller's.
    void set_threads(int n) { threads_ = n; }

private:
    int w_, h_, pairs_, half_, threads_ = 1;
    bool ok_;
    ColumnFft column_forward_, column_inverse_, row_forward_, row_inverse_;
    LargeArray<std::complex<float>> packed_, work_;
};

}  // namespace wavecam::detail
