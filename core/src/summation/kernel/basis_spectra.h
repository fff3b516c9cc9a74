// The kernel summation's kernel spectra and the product its runs take with them
// (kernel_summation.h): per run, mode m's sum over the basis kernels r,
//   total_m(q) = sum_r image_r(q) spectrum_rm(q),
// at every point q of the transform's grid. The spectra are kept in chunks of kLanes points, each
// chunk holding every (r, m) pair's real and imaginary lanes side by side, so that one pass over
// a chunk keeps a few modes' sums in registers while the basis streams past once: a product of
// B x M spectra then reads each spectrum value once per run, instead of reading and writing the
// sum at every r. Internal to core.
#pragma once
#include <complex>
#include <cstddef>
#include <vector>

namespace wavecam::detail {

class BasisSpectra {
public:
    static constexpr int kLanes = 8;

    BasisSpectra() = default;
    // `rank` basis kernels, `modes` modes, `points` points per spectrum (all zero at first).
    BasisSpectra(int rank, int modes, size_t points);

    int rank() const { return rank_; }
    int modes() const { return modes_; }
    // Points per plane of the runs' images and sums: the spectrum's, rounded up to an odd number
    // of chunks (a chunk is a cache line: planes a power-of-two multiple of it apart fall on the
    // same few cache sets, and a pass over the basis reads one line of each plane).
    size_t plane() const { return (chunks_ | 1) * kLanes; }
    size_t chunks() const { return chunks_; }
    size_t bytes() const { return values_.size() * sizeof(float); }

    // Basis kernel r's spectrum in mode m (points values).
    void set(int r, int m, const std::complex<float>* spectrum);

    // Chunk c of one run: `image` holds rank() planes, `total` modes() planes, each plane() values
    // apart (their padding beyond the points read and written as any other).
    void mix(size_t chunk, const std::complex<float>* image, std::complex<float>* total) const;

private:
    int rank_ = 0, modes_ = 0;
    size_t points_ = 0, chunks_ = 0;
    // [chunk][r][m][re lanes, im lanes]
    std::vector<float> values_;
};

}  // namespace wavecam::detail
