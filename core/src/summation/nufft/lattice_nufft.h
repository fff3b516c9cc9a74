// Non-uniform discrete Fourier sums on a rectangular lattice of nx x ny points (the pinhole's
// sampling lattice), by gridding with a compact kernel and one FFT (docs/summation.md):
//   to lattice   (type 1)  F[m, n]  = sum_s a_s exp(-i ((m - cx) x_s + (n - cy) y_s)),  0 <= m < nx, 0 <= n < ny
//   from lattice (type 2)  c_s      = sum_{m,n} G[m, n] exp(-i ((m - cx) x_s + (n - cy) y_s))
// (cx, cy = nx / 2, ny / 2: centred modes; centring() is the rest of exp(-i (m x + n y))).
// x_s, y_s in radians per lattice step, any value (the sums are 2 pi periodic in them).
// Kernel: "exponential of semicircle", exp(beta (sqrt(1 - z^2) - 1)) on |z| < 1, w grid points
// wide on a grid oversampled 2x, beta = 2.30 w (Barnett, Magland & af Klinteberg, "A parallel
// non-uniform fast Fourier transform library based on an exponential of semicircle kernel",
// SIAM J. Sci. Comput. 41 (2019)); relative RMS error about 10^(1 - w), within 2x of the tolerance
// asked (tests/core/test_lattice_nufft.cpp). Written here (about 250
// lines, tested against the direct sums) rather than taken from a library: Debian bookworm ships
// no NUFFT library (FINUFFT is not packaged), and core's own FFT (fft/) serves.
// Internal to core.
#pragma once
#include <complex>
#include <cstddef>
#include <vector>

namespace wavecam::detail {

using cfloat = std::complex<float>;

// The points of a transform: (x[s], y[s]) for s < count, in radians per lattice step.
struct LatticePoints {
    const double* x;
    const double* y;
    size_t count;
};

// Points placed on a transform's grid, for many transforms of the same points: each point's first
// grid indices and kernel weights, the points bucketed by stripe of grid rows (type 1 spreads
// stripe by stripe), and the grid lines their kernels touch.
struct PlacedPoints {
    size_t count = 0;
    std::vector<int> first_x, first_y;      // wrapped onto the grid
    std::vector<float> weight_x, weight_y;  // w per point
    std::vector<std::vector<size_t>> bucket;
    std::vector<int> rows, columns;
};

class LatticeNufft {
public:
    // `tolerance`: the relative error asked for (1e-2 .. 1e-7); `nthreads` 0 = every core.
    LatticeNufft(int nx, int ny, double tolerance, int nthreads = 0);

    int nx() const { return nx_; }
    int ny() const { return ny_; }
    int kernel_width() const { return w_; }
    int grid_x() const { return mx_; }
    int grid_y() const { return my_; }

    // exp(-i (cx x + cy y)), cx = nx / 2, cy = ny / 2: the modes are centred, m - cx, and this
    // phase of each point is the caller's, applied once per point rather than per transform.
    std::complex<double> centring(double x, double y) const;
    double centring_phase(double x, double y) const { return -((nx_ / 2) * x + (ny_ / 2) * y); }

    // (`lines`: with the grid lines they touch, which a transform of these points alone needs)
    PlacedPoints place(const LatticePoints& points, bool lines = true) const;

    // Type 1 for `batch` strength sets at once (the kernel weights of a point computed once):
    // lattices[q][n * nx + m] = sum_s a[s * batch + q] exp(-i ((m - cx) x[s] + (n - cy) y[s])).
    void to_lattice(const LatticePoints& points, const cfloat* a, int batch, cfloat* const* lattices) const;
    // Type 2 for `batch` lattices at once, weighted per point:
    // out[s] = sum_q c[s * batch + q] sum_{m,n} lattices[q][n * nx + m] exp(-i ((m - cx) x[s] + (n - cy) y[s])).
    void from_lattice(const cfloat* const* lattices, int batch, const LatticePoints& points, const cfloat* c,
                      cfloat* out) const;
    // The same for placed points (from_lattice: points [begin, end) of them, c and out indexed from begin).
    void to_lattice(const PlacedPoints& points, const cfloat* a, int batch, cfloat* const* lattices) const;
    void from_lattice(const cfloat* const* lattices, int batch, const PlacedPoints& points, size_t begin, size_t end,
                      const cfloat* c, cfloat* out) const;

    // The work of one transform in units of its parts: FFT points x log2, kernel taps per point.
    double fft_work() const;
    double taps_per_point() const { return double(w_) * w_; }

private:
    void fft2d(std::vector<cfloat>& grid, const std::vector<int>& rows, const std::vector<int>& columns) const;
    // The grid lines (of m) that the kernels of points at x (radians per step) touch, and the
    // lines of the n centred modes.
    std::vector<int> touched(const double* x, size_t count, int m) const;
    static std::vector<int> mode_lines(int n, int m);
    int nx_, ny_, mx_, my_, w_, nthreads_;
    double beta_;
    std::vector<double> deconvolve_x_, deconvolve_y_;
    std::vector<float> table_;  // the kernel, tabulated
    std::vector<std::vector<cfloat>>& workspace(int batch, size_t plane) const;
    // A transform's steps on the workspace: cleared; points spread onto it (type 1) and its rows
    // transformed to the modes; the modes onto it and transformed (type 2), points read from it.
    void clear(int batch) const;
    void spread(const PlacedPoints& points, const cfloat* a, int batch) const;
    void to_modes(int batch, const std::vector<int>& rows, cfloat* const* lattices) const;
    void from_modes(const cfloat* const* lattices, int batch, const std::vector<int>& columns) const;
    void interpolate(const PlacedPoints& points, size_t begin, size_t end, int batch, const cfloat* c,
                     cfloat* out) const;
    mutable std::vector<std::vector<cfloat>> grids_;  // one transform at a time per object
    mutable std::vector<cfloat> column_work_;         // the column transforms' work array
};

}  // namespace wavecam::detail
