// The psf summation's and far tail's 2D FFTs (core/src/complex_fft2d.h, column_fft.h) against
// the discrete Fourier transform summed directly, for sizes of every radix the transform takes
// (4, 2, 3, 5, and odd counts of stages, whose result ends in the work array), rectangular,
// with rows known to be zero, and large enough to spread over threads.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include "fft/complex_fft2d.h"
#include "fft/column_fft.h"

using wavecam::detail::ColumnFft;
using wavecam::detail::ComplexFft2D;
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
