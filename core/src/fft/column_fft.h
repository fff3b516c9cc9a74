// Complex 1D FFTs down the columns of a row-major array, every column at once: a mixed-radix
// Stockham transform (radices 4, 2, 3, 5; self-sorting, one work array of the same size), each
// butterfly applied to a whole run of columns, so the inner loops are long, contiguous and
// vectorised. The kernel summation's runs take thousands of 2D transforms of one size; down the
// columns of a row-major image every butterfly has hundreds of independent lanes, where a 1D
// library works one scalar sequence at a time. Internal to core.
//
// Stage of radix P on a length n = P m, stride s (the sub-sequences already split off):
//   y[q + s (P p + k)] = w_n^(p k) sum_j x[q + s (p + j m)] w_P^(j k),   w_n = exp(-+2 pi i / n),
// then the length-m transforms of stride P s; after the last stage the output is in natural
// order (Stockham's autosort). Sizes with a prime factor above 5 are refused (fft_friendly_size
// gives sizes without).
#pragma once
#include <complex>
#include <vector>

namespace wavecam::detail {

class ColumnFft {
public:
    ColumnFft(int length, bool inverse);

    bool ok() const { return ok_; }
    int length() const { return n_; }

    // The transform of length() rows of `columns` complex values (row r at data + r * columns),
    // columns [first, last) only; `work` holds length() x columns values (its contents are lost).
    // Unnormalised in both directions. Each stage's lanes spread over `threads` (called from
    // outside any parallel region; the stages in turn): the same values at any count.
    void transform(std::complex<float>* data, std::complex<float>* work, int columns, int first, int last,
                   int threads = 1) const;
    // As transform(), without the copy back: returns data or work, whichever holds the result
    // (work where ends_in_work(): an odd number of stages; its columns outside [first, last) are
    // not written). `source`, where given, is read instead of data by the first stage (data is
    // then only written: a transform of an array the caller keeps, with no copy first).
    std::complex<float>* transform_where(std::complex<float>* data, std::complex<float>* work, int columns, int first,
                                         int last, int threads = 1,
                                         const std::complex<float>* source = nullptr) const;
    bool ends_in_work() const { return stages_.size() % 2 == 1; }
    // The widest run of columns of `length` rows whose rows and work fit one thread's cache (a
    // multiple of 8, at least kMinBlockColumns): transform() takes wider single-thread runs a
    // block at a time.
    static int block_columns(int length);

private:
    // One thread's cache for a block of columns (transform), at least kMinBlockColumns wide.
    static constexpr size_t kCacheBytes = size_t(1) << 20;
    static constexpr int kMinBlockColumns = 16;
    // the stages over columns [first, last); returns the array holding the result
    std::complex<float>* stages(std::complex<float>* data, std::complex<float>* work, int columns, int first,
                                int last, int threads, const std::complex<float>* source = nullptr) const;

    struct Stage {
        int radix, m;                             // this stage's radix and the length after it
        std::vector<std::complex<float>> twiddle;  // [p * (radix - 1) + k - 1] = w_n^(p k)
    };
    int n_;
    bool inverse_, ok_ = true;
    std::vector<Stage> stages_;
};

// Smallest size >= n with no prime factor above 5 (the sizes ColumnFft takes), and even.
inline int fft_friendly_size(int n) {
    // (at least 2: a size of 0 never leaves the loop below; beyond 2^28 no search, a size that
    // large is only ever a cost to compare, never allocated)
    if (n < 2) return 2;
    if (n > (1 << 28)) return n;
    for (int m = n + (n & 1);; m += 2) {
        int r = m;
        for (int p : {2, 3, 5})
            while (r % p == 0) r /= p;
        if (r == 1) return m;
    }
}

}  // namespace wavecam::detail
