#include "fft/complex_fft2d.h"

#include <algorithm>
#include <vector>

#include "base/parallel.h"

namespace wavecam::detail {
namespace {

// dst (columns x rows) = the transpose of src (rows x columns), in tiles that stay in cache;
// source rows [0, rows) only.
void transpose(Team& team, const std::complex<float>* src, std::complex<float>* dst, int rows, int columns,
               int src_rows) {
    constexpr int kTile = 32;
    const int across = (columns + kTile - 1) / kTile, down = (src_rows + kTile - 1) / kTile;
    team.for_blocks(0, int64_t(down) * across, [&](int64_t tile) {
        const int r0 = int(tile / across) * kTile, c0 = int(tile % across) * kTile;
        const int r1 = std::min(r0 + kTile, src_rows), c1 = std::min(c0 + kTile, columns);
        for (int r = r0; r < r1; ++r)
            for (int c = c0; c < c1; ++c) dst[size_t(c) * rows + r] = src[size_t(r) * columns + c];
    });
}

// Columns [first, last) of a rows x columns array, spread over the team.
void columns_of(Team& t, const ColumnFft& fft, std::complex<float>* data, std::complex<float>* work, int columns,
                int first, int last) {
    const int team = t.size(), me = t.rank();
    // lane runs of at least 16 values per thread
    const int share = std::max(16, (last - first + team - 1) / team);
    const int a = first + me * share, b = std::min(last, a + share);
    if (a < b) fft.transform(data, work, columns, a, b);
    t.barrier();
}

}  // namespace

void ComplexFft2D::transform(std::complex<float>* data, int rows, const ColumnFft& row,
                             const ColumnFft& column) const {
    // scratch: the transposed array and the column transforms' work array, per calling thread
    thread_local std::vector<std::complex<float>> transposed, work;
    transposed.resize(size());
    work.resize(size());
    std::complex<float>*t = transposed.data(), *wk = work.data();
    const int busy = rows < 0 ? h_ : std::min(rows, h_);
    // (small transforms on one thread: a parallel region per transform costs more than it
    // saves, and far more where other processes share the cores)
    parallel_team(size() >= kParallelPoints ? threads_ : 1, [&](Team& team) {
        // the rows: columns of the transpose (width x height), the zero ones left alone
        transpose(team, data, t, h_, w_, busy);
        team.for_blocks(0, w_, [&](int64_t x) { std::fill(t + size_t(x) * h_ + busy, t + size_t(x + 1) * h_, 0.0f); });
        columns_of(team, row, t, wk, h_, 0, busy);
        transpose(team, t, data, w_, h_, w_);
        columns_of(team, column, data, wk, w_, 0, w_);
    });
}

void ComplexFft2D::forward(std::complex<float>* data, int rows) const {
    transform(data, rows, row_forward_, column_forward_);
}

void ComplexFft2D::inverse(std::complex<float>* data) const { transform(data, -1, row_inverse_, column_inverse_); }

}  // namespace wavecam::detail
