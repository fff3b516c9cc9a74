// The gridding NUFFT (core/src/lattice_nufft.h) against the direct sums it replaces, term by
// term in double precision: both types, odd and even lattices, points anywhere (wrapped).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include "summation/nufft/lattice_nufft.h"

namespace {
using wavecam::detail::cfloat;
using wavecam::detail::LatticeNufft;

struct Points {
    std::vector<double> x, y;
    std::vector<cfloat> a;
};

Points random_points(size_t n, double spread, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-spread, spread), c(-1, 1);
    Points p;
    for (size_t s = 0; s < n; ++s) {
        p.x.push_back(u(rng));
        p.y.push_back(u(rng));
        p.a.emplace_back(float(c(rng)), float(c(rng)));
    }
    return p;
}

double relative_rms(const std::vector<cfloat>& got, const std::vector<std::complex<double>>& want) {
    double e = 0, n = 0;
    for (size_t i = 0; i < want.size(); ++i) {
        e += std::norm(std::complex<double>(got[i]) - want[i]);
        n += std::norm(want[i]);
    }
    return std::sqrt(e / n);
}

struct Case {
    int nx, ny;
    double tolerance, spread;
};

class LatticeNufftTest : public ::testing::TestWithParam<Case> {};

TEST_P(LatticeNufftTest, ToLatticeMatchesTheDirectSum) {
    const Case c = GetParam();
    const Points p = random_points(300, c.spread, 7);
    LatticeNufft t(c.nx, c.ny, c.tolerance, 2);
    // two strength sets at once: the points' own and twice them, both centred by the caller
    std::vector<cfloat> a;
    for (size_t s = 0; s < p.a.size(); ++s) {
        const cfloat v(std::complex<double>(p.a[s]) * t.centring(p.x[s], p.y[s]));
        a.push_back(v);
        a.push_back(2.0f * v);
    }
    std::vector<cfloat> got(size_t(c.nx) * c.ny), twice(got.size());
    cfloat* lattices[2] = {got.data(), twice.data()};
    t.to_lattice({p.x.data(), p.y.data(), p.a.size()}, a.data(), 2, lattices);
    for (size_t i = 0; i < got.size(); ++i) ASSERT_NEAR(std::abs(twice[i] - 2.0f * got[i]), 0.0, 1e-4 * std::abs(got[i]) + 1e-6);
    std::vector<std::complex<double>> want(got.size());
    for (int n = 0; n < c.ny; ++n)
        for (int m = 0; m < c.nx; ++m)
            for (size_t s = 0; s < p.a.size(); ++s)
                want[size_t(n) * c.nx + m] += std::complex<double>(p.a[s]) * std::polar(1.0, -(m * p.x[s] + n * p.y[s]));
    EXPECT_LT(relative_rms(got, want), 2 * c.tolerance);  // "about tolerance" (lattice_nufft.h)
}

TEST_P(LatticeNufftTest, FromLatticeMatchesTheDirectSum) {
    const Case c = GetParam();
    const Points p = random_points(300, c.spread, 9);
    const Points g = random_points(size_t(c.nx) * c.ny, 1, 11);
    LatticeNufft t(c.nx, c.ny, c.tolerance, 2);
    // the lattice given twice, weighted 0.25 i and 0.75 per point: (0.75 + 0.25 i) times the one
    // transform, then centred
    std::vector<cfloat> got(p.x.size());
    const cfloat* lattices[2] = {g.a.data(), g.a.data()};
    std::vector<cfloat> weights;
    for (size_t s = 0; s < p.x.size(); ++s) weights.insert(weights.end(), {cfloat(0, 0.25f), cfloat(0.75f)});
    t.from_lattice(lattices, 2, {p.x.data(), p.y.data(), p.x.size()}, weights.data(), got.data());
    const std::complex<double> weight(0.75, 0.25);
    for (size_t s = 0; s < p.x.size(); ++s)
        got[s] = cfloat(std::complex<double>(got[s]) * t.centring(p.x[s], p.y[s]) / weight);
    std::vector<std::complex<double>> want(got.size());
    for (size_t s = 0; s < p.x.size(); ++s)
        for (int n = 0; n < c.ny; ++n)
            for (int m = 0; m < c.nx; ++m)
                want[s] += std::complex<double>(g.a[size_t(n) * c.nx + m]) * std::polar(1.0, -(m * p.x[s] + n * p.y[s]));
    EXPECT_LT(relative_rms(got, want), 2 * c.tolerance);  // "about tolerance" (lattice_nufft.h)
}

INSTANTIATE_TEST_SUITE_P(Lattices, LatticeNufftTest,
                         ::testing::Values(Case{64, 64, 1e-3, M_PI}, Case{63, 41, 1e-5, M_PI}, Case{50, 70, 1e-6, 3 * M_PI},
                                           Case{1, 17, 1e-5, M_PI}, Case{128, 96, 1e-4, 0.5}));

}  // namespace
