// Parts of the exact method's evaluation checked on their own against independent math
// (docs/summation.md): the interpolative decomposition of node functions
// (core/src/node_skeleton.h), the band-limited stencil that reads and spreads off-lattice
// samples (core/src/band_limited_stencil.h), the film points' average of a pixel
// (core/src/pixel_average.h), and the few kernels the psf summation's runs transform
// (core/src/kernel_basis.h).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include "band_limited_stencil.h"
#include "kernel_basis.h"
#include "node_skeleton.h"
#include "pixel_average.h"

using wavecam::detail::BandLimitedStencil;
using wavecam::detail::node_skeleton;
using cdouble = std::complex<double>;

namespace {

// Each function rebuilt from the skeleton's rows: the largest RMS error over the points.
double worst_rebuild(const std::vector<cdouble>& v, int functions, int points,
                     const wavecam::detail::NodeSkeleton& sk) {
    double worst = 0;
    for (int q = 0; q < functions; ++q) {
        double e = 0;
        for (int i = 0; i < points; ++i) {
            cdouble r = 0;
            for (int j = 0; j < sk.rank(); ++j)
                r += sk.coeff[size_t(q) * sk.rank() + j] * v[size_t(sk.rows[j]) * points + i];
            e += std::norm(r - v[size_t(q) * points + i]);
        }
        worst = std::max(worst, std::sqrt(e / points));
    }
    return worst;
}

}  // namespace

// 20 functions built from 3 random ones: rank 3, rebuilt to rounding.
TEST(NodeSkeleton, FindsTheRankOfAnExactlyLowRankSet) {
    std::mt19937 rng(3);
    std::normal_distribution<double> g;
    const int functions = 20, points = 50, rank = 3;
    std::vector<cdouble> basis(rank * points), v(functions * points);
    for (cdouble& b : basis) b = {g(rng), g(rng)};
    for (int q = 0; q < functions; ++q) {
        cdouble c[rank] = {{g(rng), g(rng)}, {g(rng), g(rng)}, {g(rng), g(rng)}};
        for (int i = 0; i < points; ++i)
            for (int l = 0; l < rank; ++l) v[q * points + i] += c[l] * basis[l * points + i];
    }
    const auto sk = node_skeleton(v, functions, points, 1e-9);
    EXPECT_EQ(sk.rank(), rank);
    EXPECT_LT(worst_rebuild(v, functions, points, sk), 1e-9);
}

// Chirps exp(i a x^2), a in [0, 3] rad, on [-1, 1]: a smooth family of low numerical rank, every
// member rebuilt within the tolerance asked; a tighter tolerance takes more rows.
TEST(NodeSkeleton, RebuildsASmoothFamilyWithinTheTolerance) {
    const int functions = 40, points = 81;
    std::vector<cdouble> v(functions * points);
    for (int q = 0; q < functions; ++q)
        for (int i = 0; i < points; ++i) {
            const double a = 3.0 * q / (functions - 1), x = -1.0 + 2.0 * i / (points - 1);
            v[q * points + i] = std::polar(1.0, a * x * x);
        }
    int last = 0;
    for (double tol : {1e-3, 1e-5, 1e-8}) {
        const auto sk = node_skeleton(v, functions, points, tol);
        EXPECT_LE(worst_rebuild(v, functions, points, sk), tol) << tol;
        EXPECT_LT(sk.rank(), 15) << tol;
        EXPECT_GT(sk.rank(), last) << tol;
        last = sk.rank();
    }
}

// exp(i nu x) off the lattice from its lattice values, for random x and nu within the band,
// against the exponential itself; where the band leaves no room, the stencil says so.
TEST(BandLimitedStencil, InterpolatesEveryFrequencyInItsBand) {
    std::mt19937 rng(9);
    for (double band : {0.3, 0.5, 0.68, 0.9}) {
        const double nu_max = band * M_PI, tol = band < 0.6 ? 1e-4 : 1e-2;
        const BandLimitedStencil st(nu_max, tol);
        ASSERT_TRUE(st.usable()) << band;
        std::uniform_real_distribution<double> ux(-40, 40), un(-nu_max, nu_max);
        double worst = 0, w[64];
        for (int t = 0; t < 2000; ++t) {
            const double x = ux(rng), nu = un(rng);
            const long first = st.weights(x, w);
            cdouble s = 0;
            for (int i = 0; i < st.width(); ++i) s += w[i] * std::polar(1.0, nu * double(first + i));
            worst = std::max(worst, std::abs(s - std::polar(1.0, nu * x)));
        }
        std::printf("band %.2f pi, %d points: worst error %.3g (asked %.0e)\n", band, st.width(), worst, tol);
        EXPECT_LE(worst, tol) << band;
    }
    EXPECT_FALSE(BandLimitedStencil(0.95 * M_PI, 1e-3).usable());
    EXPECT_FALSE(BandLimitedStencil(M_PI, 1e-2).usable());
}

// n points per pixel side against the pixel's area average, for fringes cos(2 pi f x + a) of
// every phase: the largest difference over frequencies up to the cutoff, weighted by a circular
// pupil's OTF, is what pixel_average_error states (to the grid's resolution); and it falls as
// points are added.
TEST(PixelAverage, StatesTheMidpointRulesErrorOverTheOpticsBand) {
    for (double pfc : {0.3, 1.32, 5.6}) {
        double last = INFINITY;
        for (int n : {1, 2, 4, 8}) {
            double worst = 0;
            for (int i = 1; i <= 200; ++i) {
                const double nu = i / 200.0, x = pfc * nu;  // x = f p
                const double otf = 2 / M_PI * (std::acos(nu) - nu * std::sqrt(1 - nu * nu));
                for (double a : {0.0, 0.7, 1.9}) {
                    // exact pixel average of cos(2 pi x t + a), t in [-1/2, 1/2]: by its antiderivative
                    const double exact = (std::sin(M_PI * x + a) - std::sin(-M_PI * x + a)) / (2 * M_PI * x);
                    double points = 0;
                    for (int j = 0; j < n; ++j) points += std::cos(2 * M_PI * x * ((j + 0.5) / n - 0.5) + a) / n;
                    worst = std::max(worst, std::fabs(points - exact) * otf);
                }
            }
            const double stated = wavecam::detail::pixel_average_error(n, pfc);
            EXPECT_NEAR(stated, worst, 0.02 * stated + 1e-3) << pfc << " " << n;
            EXPECT_LE(stated, last + 1e-9) << pfc << " " << n;
            last = stated;
        }
    }
}

namespace {

// Kernels (rows of `points` values) as combinations of `rank` random vectors, plus `noise` times
// a random vector of each kernel's own.
std::vector<std::vector<cdouble>> kernels_of_rank(int K, int points, int rank, double noise, uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    auto random_vector = [&] {
        std::vector<cdouble> v(points);
        for (auto& x : v) x = {g(rng), g(rng)};
        return v;
    };
    std::vector<std::vector<cdouble>> base(rank);
    for (auto& b : base) b = random_vector();
    std::vector<std::vector<cdouble>> k(K, std::vector<cdouble>(points, 0.0));
    for (int i = 0; i < K; ++i) {
        for (int r = 0; r < rank; ++r) {
            const cdouble c{g(rng), g(rng)};
            for (int t = 0; t < points; ++t) k[i][t] += c * base[r][t];
        }
        const auto own = random_vector();
        for (int t = 0; t < points; ++t) k[i][t] += noise * own[t];
    }
    return k;
}

std::vector<cdouble> gram_of(const std::vector<std::vector<cdouble>>& k) {
    const size_t K = k.size();
    std::vector<cdouble> g(K * K);
    for (size_t i = 0; i < K; ++i)
        for (size_t j = 0; j < K; ++j)
            for (size_t t = 0; t < k[i].size(); ++t) g[i * K + j] += k[i][t] * std::conj(k[j][t]);
    return g;
}

// Each kernel rebuilt from the basis (basis_r = sum_k mix k_k, kernel = sum_r coefficient basis_r):
// the largest power left out, relative to the kernel's.
double worst_left_out(const std::vector<std::vector<cdouble>>& k, const wavecam::detail::KernelBasis& b) {
    const int K = int(k.size()), P = int(k[0].size());
    std::vector<std::vector<cdouble>> basis(b.rank, std::vector<cdouble>(P, 0.0));
    for (int r = 0; r < b.rank; ++r)
        for (int i = 0; i < K; ++i)
            for (int t = 0; t < P; ++t) basis[r][t] += b.mix[size_t(r) * K + i] * k[i][t];
    double worst = 0;
    for (int i = 0; i < K; ++i) {
        double e = 0, n = 0;
        for (int t = 0; t < P; ++t) {
            cdouble v = 0;
            for (int r = 0; r < b.rank; ++r) v += b.coefficient[size_t(i) * b.rank + r] * basis[r][t];
            e += std::norm(v - k[i][t]);
            n += std::norm(k[i][t]);
        }
        worst = std::max(worst, e / n);
    }
    return worst;
}

}  // namespace

// Kernels that are combinations of five vectors: five basis kernels rebuild each to rounding.
TEST(KernelBasis, FindsTheRankOfAnExactlyLowRankSet) {
    const auto k = kernels_of_rank(20, 300, 5, 0.0, 3);
    const auto b = wavecam::detail::kernel_basis(gram_of(k), 20);
    EXPECT_EQ(b.rank, 5);
    EXPECT_LT(worst_left_out(k, b), 1e-12);
}

// Each kernel a little apart from a rank-4 family (its own part about 1e-6 of its power): the
// basis keeps the family alone where the tolerance allows that, more where it does not, and no
// kernel loses more than asked.
TEST(KernelBasis, LeavesNoKernelMoreThanTheTolerance) {
    const auto k = kernels_of_rank(30, 400, 4, 3e-3, 5);
    for (const double tolerance : {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8}) {
        const auto b = wavecam::detail::kernel_basis(gram_of(k), 30, tolerance);
        EXPECT_LE(worst_left_out(k, b), tolerance) << tolerance;
        if (tolerance >= 1e-3) {
            EXPECT_EQ(b.rank, 4) << tolerance;
        }
        if (tolerance <= 1e-8) {
            EXPECT_GT(b.rank, 4) << tolerance;
        }
    }
}

// Kernels with nothing in common, or more than the decomposition takes: each its own.
TEST(KernelBasis, IsTheKernelsThemselvesWhenNothingIsShared) {
    const auto k = kernels_of_rank(12, 100, 0, 1.0, 7);
    const auto b = wavecam::detail::kernel_basis(gram_of(k), 12);
    ASSERT_EQ(b.rank, 12);
    for (int i = 0; i < 12; ++i)
        for (int r = 0; r < 12; ++r) EXPECT_EQ(b.coefficient[size_t(i) * 12 + r], cdouble(i == r ? 1.0 : 0.0));
    const int many = wavecam::detail::kMaxBasisKernels + 1;
    EXPECT_EQ(wavecam::detail::kernel_basis({}, many).rank, many);
}
