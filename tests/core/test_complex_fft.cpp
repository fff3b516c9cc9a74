// Core's FFTs (core/src/fft/: complex 2D, real 2D, lines, all through column_fft.h) against the
// discrete Fourier transform summed directly, for sizes of every radix the transform takes (4,
// 2, 3, 5, and odd counts of stages, whose result ends in the work array), rectangular, with
// rows or columns known to be zero, and large enough to spread over threads.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include "fft/column_fft.h"
#include "fft/complex_fft2d.h"
#include "fft/line_fft.h"
#include "fft/real_fft2d.h"

using wavecam::detail::ColumnFft;
using wavecam::detail::ComplexFft2D;
using wavecam::detail::LineFft;
using wavecam::detail::RealFft2D;
using cfloat = std::complex<float>;

namespace {

std::vector<cfloat> random_image(int w, int h, int rows, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> n;
    std::vector<cfloat> v(size_t(w) * h, 0.0f);
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < w; ++x) v[size_t(y) * w + x] = {n(rng), n(rng)};
    return v;
}

// sum_{x,y} v(x, y) exp(sign 2 pi i (kx x / w + ky y / h)), in double, separably
std::vector<std::complex<double>> direct_dft(const std::vector<cfloat>& v, int w, int h, double sign) {
    std::vector<std::complex<double>> rows(v.size()), out(v.size());
    for (int y = 0; y < h; ++y)
        for (int kx = 0; kx < w; ++kx) {
            std::complex<double> s = 0;
            for (int x = 0; x < w; ++x)
                s += std::complex<double>(v[size_t(y) * w + x]) * std::polar(1.0, sign * 2 * M_PI * double(kx) * x / w);
            rows[size_t(y) * w + kx] = s;
        }
    for (int kx = 0; kx < w; ++kx)
        for (int ky = 0; ky < h; ++ky) {
            std::complex<double> s = 0;
            for (int y = 0; y < h; ++y) s += rows[size_t(y) * w + kx] * std::polar(1.0, sign * 2 * M_PI * double(ky) * y / h);
            out[size_t(ky) * w + kx] = s;
        }
    return out;
}

// RMS of a - b over RMS of b
double relative_rms(const std::vector<cfloat>& a, const std::vector<std::complex<double>>& b) {
    double e = 0, r = 0;
    for (size_t q = 0; q < a.size(); ++q) {
        e += std::norm(std::complex<double>(a[q]) - b[q]);
        r += std::norm(b[q]);
    }
    return std::sqrt(e / r);
}

}  // namespace

TEST(ComplexFft, MatchesTheDirectTransformForEveryRadix) {
    // stages (radix 4 first, then 2, 3, 5): 2 = 2; 6 = 2 3; 32 = 4 4 2; 90 = 2 3 3 5; 60 = 4 3 5;
    // 100 = 4 5 5; 150 = 2 3 5 5; 8 = 4 2; 12 = 4 3; 45 = 3 3 5 (odd counts end in the work array)
    const int sizes[][2] = {{2, 6}, {32, 90}, {60, 100}, {150, 8}, {12, 45}};
    unsigned seed = 1;
    for (const auto& s : sizes) {
        const int w = s[0], h = s[1];
        const ComplexFft2D fft(w, h, 2);
        ASSERT_TRUE(fft.ok());
        for (int rows : {h, h / 2 + 1}) {
            std::vector<cfloat> v = random_image(w, h, rows, seed++);
            const auto forward = direct_dft(v, w, h, -1), backward = direct_dft(v, w, h, +1);
            std::vector<cfloat> f = v, b = v;
            fft.forward(f.data(), rows);
            fft.inverse(b.data());
            EXPECT_LT(relative_rms(f, forward), 1e-6) << w << " x " << h << ", rows " << rows;
            EXPECT_LT(relative_rms(b, backward), 1e-6) << w << " x " << h;
        }
    }
}

TEST(ComplexFft, LargeTransformsSpreadOverThreadsRoundTrip) {
    // above kParallelPoints: columns and transposes shared between the threads
    const int w = 270, h = 256;
    ASSERT_GE(size_t(w) * h, ComplexFft2D::kParallelPoints);
    const ComplexFft2D fft(w, h, 2);
    const std::vector<cfloat> v = random_image(w, h, 200, 7);
    std::vector<cfloat> t = v;
    fft.forward(t.data(), 200);
    // one row of the spectrum against the direct sum: the zero-frequency row is every row's sum
    for (int kx : {0, 1, 77, 269}) {
        std::complex<double> s = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                s += std::complex<double>(v[size_t(y) * w + x]) * std::polar(1.0, -2 * M_PI * double(kx) * x / w);
        EXPECT_LT(std::abs(std::complex<double>(t[kx]) - s), 1e-5 * std::sqrt(double(w) * h) * 2) << kx;
    }
    fft.inverse(t.data());
    double e = 0, r = 0;
    for (size_t q = 0; q < v.size(); ++q) {
        e += std::norm(t[q] / float(w * h) - v[q]);
        r += std::norm(v[q]);
    }
    EXPECT_LT(std::sqrt(e / r), 1e-6);
}

TEST(ComplexFft, RefusesSizesWithLargerPrimeFactors) {
    EXPECT_FALSE(ColumnFft(14, false).ok());
    EXPECT_TRUE(ColumnFft(wavecam::detail::fft_friendly_size(14), false).ok());
}

TEST(RealFft, MatchesTheDirectTransformAndRoundTrips) {
    // widths even (columns go in pairs), heights even and odd; spectrum S[kx][ky], ky <= h/2
    const int sizes[][2] = {{2, 6}, {32, 90}, {60, 100}, {150, 8}, {12, 45}, {90, 15}};
    unsigned seed = 11;
    for (const auto& s : sizes) {
        const int w = s[0], h = s[1];
        RealFft2D fft(w, h);
        ASSERT_TRUE(fft.ok());
        ASSERT_EQ(fft.spectrum_rows(), w);
        ASSERT_EQ(fft.spectrum_columns(), h / 2 + 1);
        // columns outside [first, last) zero, the hint given: a tile in its padded frame, an
        // anchor's hat in it, a kernel wrapped round the first column
        const int ranges[][2] = {{0, w}, {0, w / 2 + 1}, {1, w / 2 + 1}, {w - 1, w + 2}};
        for (const auto& range : ranges) {
            const int first = range[0], last = range[1];
            std::vector<cfloat> complex_image = random_image(w, h, h, seed++);
            std::vector<float> image(size_t(w) * h);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    complex_image[size_t(y) * w + x] = image[size_t(y) * w + x] =
                        (x >= first && x < last) || x + w < last ? complex_image[size_t(y) * w + x].real() : 0.0f;
            const auto forward = direct_dft(complex_image, w, h, -1);
            std::vector<cfloat> spectrum(fft.spectrum_size());
            fft.forward(image.data(), spectrum.data(), first, last);
            double e = 0, r = 0;
            for (int kx = 0; kx < w; ++kx)
                for (int ky = 0; ky <= h / 2; ++ky) {
                    const std::complex<double> want = forward[size_t(ky) * w + kx];
                    e += std::norm(std::complex<double>(spectrum[size_t(kx) * (h / 2 + 1) + ky]) - want);
                    r += std::norm(want);
                }
            EXPECT_LT(std::sqrt(e / r), 1e-6) << w << " x " << h << ", columns " << first << " to " << last;
            std::vector<float> back(size_t(w) * h);
            fft.inverse(spectrum.data(), back.data());
            e = r = 0;
            for (size_t q = 0; q < image.size(); ++q) {
                e += std::pow(back[q] / float(w * h) - image[q], 2);
                r += std::pow(image[q], 2);
            }
            EXPECT_LT(std::sqrt(e / r), 1e-6) << w << " x " << h;
        }
    }
}

// A transform spread over threads (a whole frame's tile) gives the same values as one thread's,
// with the stages' results left in either array: both parities of the column and row stage
// counts (64 = 4 4 4 and 100 = 4 5 5: odd; 48 = 4 4 3 and 90 = 2 3 3 5: even).
TEST(RealFft, SpreadOverThreadsGivesTheSameValues) {
    const int sizes[][2] = {{64, 100}, {48, 90}, {64, 90}, {48, 100}};
    unsigned seed = 101;
    for (const auto& s : sizes) {
        const int w = s[0], h = s[1];
        RealFft2D one(w, h), two(w, h);
        two.set_threads(2);
        for (const auto& range : {std::pair<int, int>{0, w}, {w - 3, w + 5}}) {
            const std::vector<cfloat> values = random_image(w, h, h, seed++);
            std::vector<float> image(size_t(w) * h);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    image[size_t(y) * w + x] = (x >= range.first && x < range.second) || x + w < range.second
                                                   ? values[size_t(y) * w + x].real()
                                                   : 0.0f;
            std::vector<cfloat> a(one.spectrum_size()), b(two.spectrum_size());
            one.forward(image.data(), a.data(), range.first, range.second);
            two.forward(image.data(), b.data(), range.first, range.second);
            EXPECT_EQ(a, b) << w << " x " << h;
            std::vector<float> back_a(image.size()), back_b(image.size());
            one.inverse(a.data(), back_a.data());
            two.inverse(b.data(), back_b.data());
            EXPECT_EQ(back_a, back_b) << w << " x " << h;
            double e = 0, r = 0;
            for (size_t q = 0; q < image.size(); ++q) {
                e += std::pow(back_b[q] / float(w * h) - image[q], 2);
                r += std::pow(image[q], 2);
            }
            EXPECT_LT(std::sqrt(e / r), 1e-6) << w << " x " << h;
        }
    }
}

TEST(LineFft, TransformsEveryLineInPlaceWhereverItLies) {
    // lines of a grid wider than they are long, every other row, both directions
    for (const int n : {6, 32, 45, 100}) {
        const int stride = n + 3, count = 7;
        std::vector<cfloat> grid = random_image(stride, 2 * count, 2 * count, unsigned(n));
        const std::vector<cfloat> before = grid;
        for (const bool inverse : {false, true}) {
            grid = before;
            LineFft fft(n, inverse);
            ASSERT_TRUE(fft.ok());
            fft.transform(count, [&](int k) { return &grid[size_t(2 * k) * stride]; });
            double e = 0, r = 0;
            for (int row = 0; row < 2 * count; ++row)
                for (int k = 0; k < stride; ++k) {
                    std::complex<double> want = before[size_t(row) * stride + k];
                    if (row % 2 == 0 && k < n) {
                        want = 0;
                        for (int x = 0; x < n; ++x)
                            want += std::complex<double>(before[size_t(row) * stride + x]) *
                                    std::polar(1.0, (inverse ? 2 : -2) * M_PI * double(k) * x / n);
                    }
                    e += std::norm(std::complex<double>(grid[size_t(row) * stride + k]) - want);
                    r += std::norm(want);
                }
            EXPECT_LT(std::sqrt(e / r), 1e-6) << n << (inverse ? " inverse" : " forward");
        }
    }
}
