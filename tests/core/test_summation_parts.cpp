// Parts of the point sums' evaluation checked on their own against independent math
// (docs/summation.md): the interpolative decomposition of node functions
// (core/src/node_skeleton.h), the band-limited stencil that reads and spreads off-lattice
// samples (core/src/band_limited_stencil.h), the film points' average of a pixel
// (core/src/pixel_average.h), the few kernels and sub-point modes the kernel summation's runs
// transform (core/src/kernel_basis.h), its kernels' own pinhole lattice and the memo that keeps
// them for a wavelength's two parts (core/src/summation/kernel/kernel_summation.h); and that the point sums' tests
// re-run through every row of the evaluators' table (tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <cmath>
#include <array>
#include <complex>
#include <iterator>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "summation/nufft/band_limited_stencil.h"
#include "summation/kernel/kernel_summation.h"
#include "summation/kernel/kernel_basis.h"
#include "summation/nufft/node_skeleton.h"
#include "summation/pixel_average.h"
#include "summation/summation_evaluator.h"

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

// Designs are shared between bands and tolerances close to each other (each served by the
// design for a band rounded up and a tolerance rounded down): whatever was asked before, a
// stencil meets its own band and tolerance, checked at random points and frequencies.
TEST(BandLimitedStencil, SharedDesignsMeetEveryAskedBandAndTolerance) {
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> ub(0.2, 0.85), ut(-4.5, -2.0), ux(-10, 10), u01(0, 1);
    double band = 0.5, exponent = -3;
    for (int ask = 0; ask < 40; ++ask) {
        // every other ask a neighbour of the last: the same rounded key
        if (ask % 2 == 0) band = ub(rng), exponent = ut(rng);
        else band += 0.001, exponent += 0.01;
        const double nu_max = band * M_PI, tol = std::pow(10.0, exponent);
        const BandLimitedStencil st(nu_max, tol);
        ASSERT_TRUE(st.usable()) << band << " " << tol;
        EXPECT_LE(st.error(), tol) << band;
        double worst = 0, w[64];
        for (int t = 0; t < 300; ++t) {
            const double x = ux(rng), nu = nu_max * (2 * u01(rng) - 1);
            const long first = st.weights(x, w);
            cdouble s = 0;
            for (int i = 0; i < st.width(); ++i) s += w[i] * std::polar(1.0, nu * double(first + i));
            worst = std::max(worst, std::abs(s - std::polar(1.0, nu * x)));
        }
        EXPECT_LE(worst, tol) << "band " << band << " pi, tolerance " << tol;
    }
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

// The sub-points' modes keep what the runs sum, sum_sub |U_sub|^2: for sub-point fields that
// sample one band-limited field (n x n points per pixel of a field 2.5 fringes per pixel wide),
// their mix is orthonormal, fewer than the sub-points, and loses at most the tolerance of any
// kernel's power at any position summed; the incoherent sum (Re U, linear) takes one mode of ones.
TEST(SubPointModes, KeepTheSubPointsPowerInFewerModes) {
    const int n = 6, S = n * n, P = 15 * 15, K = 5;
    std::mt19937 rng(3);
    std::normal_distribution<double> gauss;
    std::vector<std::vector<cdouble>> kernels(K, std::vector<cdouble>(size_t(S) * P));
    for (auto& k : kernels) {
        // a random field of plane waves within 1.25 cycles per pixel on each axis
        std::vector<std::array<double, 4>> waves(24);
        for (auto& w : waves) {
            std::uniform_real_distribution<double> band(-1.25, 1.25);
            w = {band(rng), band(rng), gauss(rng), gauss(rng)};
        }
        for (int sub = 0; sub < S; ++sub)
            for (int t = 0; t < P; ++t) {
                const double x = t % 15 + (sub % n + 0.5) / n, y = t / 15 + (sub / n + 0.5) / n;
                cdouble v = 0;
                for (const auto& w : waves)
                    v += cdouble(w[2], w[3]) * std::polar(1.0, 2 * M_PI * (w[0] * x + w[1] * y));
                k[size_t(sub) * P + t] = v;
            }
    }
    const wavecam::detail::SubPointModes modes = wavecam::detail::sub_point_modes(kernels, S, false);
    ASSERT_GT(modes.count, 0);
    EXPECT_LT(modes.count, S);
    for (int a = 0; a < modes.count; ++a)
        for (int b = 0; b < modes.count; ++b) {
            cdouble dot = 0;
            for (int sub = 0; sub < S; ++sub)
                dot += modes.weight[size_t(a) * S + sub] * std::conj(modes.weight[size_t(b) * S + sub]);
            EXPECT_NEAR(std::abs(dot - cdouble(a == b ? 1.0 : 0.0)), 0.0, 1e-9) << a << " " << b;
        }
    for (const auto& k : kernels) {
        double all = 0, kept = 0;
        for (int t = 0; t < P; ++t) {
            for (int sub = 0; sub < S; ++sub) all += std::norm(k[size_t(sub) * P + t]);
            for (int m = 0; m < modes.count; ++m) {
                cdouble u = 0;
                for (int sub = 0; sub < S; ++sub) u += modes.weight[size_t(m) * S + sub] * k[size_t(sub) * P + t];
                kept += std::norm(u);
            }
        }
        EXPECT_LE(kept, all * (1 + 1e-12));
        EXPECT_GE(kept, all * (1 - wavecam::detail::kSubPointTolerance));
    }
    std::printf("%d modes of %d sub-points\n", modes.count, S);
    const wavecam::detail::SubPointModes one = wavecam::detail::sub_point_modes(kernels, S, true);
    ASSERT_EQ(one.count, 1);
    for (const cdouble w : one.weight) EXPECT_EQ(w, cdouble(1.0));
}

// The kernel summation's kernels' own pinhole lattice gives the kernel the frame's lattice gives: one source at
// the corner of a 50 degree frame (f = 50 mm, 0.3 mm pinhole, 64 x 64, planar depth 1 m), direct
// sums to the film points of the 9 x 9 pixels round its image, on the frame's lambda / 2 lattice
// and on kernel_lattice_pitch's, many times coarser. Powers within 1e-3 of the peak everywhere,
// the light within 1e-3.
TEST(KernelLattice, GivesTheKernelTheFramesLatticeGives) {
    using namespace wavecam;
    const double lambda = 550e-9;
    detail::KernelSummationSpec spec;
    spec.camera = {64, 64, 50 * M_PI / 180, 50e-3};
    spec.aperture = {ApertureShape::Circle, 0.3e-3};
    spec.wavelength = lambda;
    spec.max_inverse_depth = 1.0;
    spec.subsamples = 1;
    const double fine = sample_pitch(lambda), coarse = detail::kernel_lattice_pitch(spec, fine);
    EXPECT_GT(coarse, 4 * fine);
    const PinholeCamera& c = spec.camera;
    double u, v;
    c.tangent(2.5, 2.5, u, v);
    const std::vector<PointSource> one{{u, v, 1.0, false, 1.0, 0.0}};
    FilmPoints film;
    film.film_distance = c.film_distance;
    for (int dy = -4; dy <= 4; ++dy)
        for (int dx = -4; dx <= 4; ++dx) {
            c.tangent(2.5 + dx, 2.5 + dy, u, v);
            film.x.push_back(float(-c.film_distance * u));
            film.y.push_back(float(-c.film_distance * v));
        }
    auto kernel = [&](double pitch) {
        const ApertureSamples samples = sample_aperture(spec.aperture, pitch);
        SummationSettings direct;
        direct.summation = Summation::Direct;
        SummationPlan in = SummationPlan::create(ComputeDevice{}, SumKind::SourcesToPinhole, samples, lambda, direct);
        SummationPlan out = SummationPlan::create(ComputeDevice{}, SumKind::PinholeToFilm, samples, lambda, direct);
        EXPECT_TRUE(in.set_points(one).ok());
        EXPECT_TRUE(out.set_points(film).ok());
        PinholeField field;
        EXPECT_TRUE(in.execute(source_weights(one), field).ok());
        std::vector<cdouble> u(film.size(), 0.0);
        EXPECT_TRUE(out.execute(field, u.data()).ok());
        std::vector<double> power;
        for (const cdouble x : u) power.push_back(std::norm(x));
        return power;
    };
    const std::vector<double> a = kernel(fine), b = kernel(coarse);
    double peak = 0, worst = 0, ta = 0, tb = 0;
    for (size_t t = 0; t < a.size(); ++t) {
        peak = std::max(peak, a[t]);
        ta += a[t];
        tb += b[t];
    }
    for (size_t t = 0; t < a.size(); ++t) worst = std::max(worst, std::abs(a[t] - b[t]) / peak);
    std::printf("lattice %.3g um against %.3g um: worst %.2e of the peak, light %.6f\n", coarse * 1e6, fine * 1e6,
                worst, tb / ta);
    EXPECT_LT(worst, 1e-3);
    EXPECT_NEAR(tb / ta, 1.0, 1e-3);
}

// A job's memo makes a convolution once for the calls that ask for the same one (a wavelength's
// positive and negative power) and again when the wavelength changes; a call through it gives
// the image a call without it gives, bit for bit.
TEST(KernelSummationMemo, KeepsTheConvolutionForTheSameWavelength) {
    using namespace wavecam;
    const PinholeCamera camera{12, 12, 30 * M_PI / 180, 2e-3};
    std::vector<float> depth(144, 1.0f), first(144), second(144);
    for (size_t p = 0; p < 144; ++p) {
        first[p] = float((p * 37 % 11) / 10.0);
        second[p] = float((p * 53 % 7) / 6.0);
    }
    SceneSumSettings s;
    s.aperture = {ApertureShape::Circle, 0.05e-3};
    s.summation = Summation::Kernel;
    s.runs = 2;
    detail::KernelSummationMemo memo;
    int made = 0;
    detail::KernelSummationSpec spec;
    spec.camera = camera;
    spec.aperture = s.aperture;
    spec.wavelength = 550e-9;
    spec.max_inverse_depth = 1.0;
    spec.subsamples = 2;
    const double pitch = detail::kernel_lattice_pitch(spec, sample_pitch(550e-9));
    auto unit = [&camera](double x, double y, double w) {
        double u, v;
        camera.tangent(x, y, u, v);
        const double z = w > 0 ? 1 / w : 1.0;
        return w > 0 ? PointSource{z * u, z * v, z, false, 1.0, 0.0}
                     : PointSource{u / std::hypot(u, v, 1.0), v / std::hypot(u, v, 1.0), 1 / std::hypot(u, v, 1.0),
                                   true, 1.0, 0.0};
    };
    auto make = [&] {
        ++made;
        return detail::KernelSummation::create(ComputeDevice{}, spec, pitch, unit, {});
    };
    auto a = memo.get(spec, pitch, make), b = memo.get(spec, pitch, make);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_EQ(made, 1);
    EXPECT_EQ(a.value.get(), b.value.get());
    spec.wavelength = 600e-9;
    ASSERT_TRUE(memo.get(spec, pitch, make).ok());
    EXPECT_EQ(made, 2);

    detail::KernelSummationMemo job;
    for (const std::vector<float>* power : {&first, &second}) {
        const MonochromeScene scene{camera, power->data(), depth.data(), DepthMeaning::Planar};
        std::vector<float> with(144, 0.0f), without(144, 0.0f);
        ASSERT_TRUE(detail::diffract_monochrome(scene, 550e-9, s, ComputeDevice{}, with.data(), {}, nullptr, &job).ok());
        ASSERT_TRUE(diffract_monochrome(scene, 550e-9, s, ComputeDevice{}, without.data()).ok());
        for (size_t p = 0; p < 144; ++p) ASSERT_EQ(with[p], without[p]) << p;
    }
}

// Every row of the evaluators' table re-runs the point sums' tests through its word
// (tests/CMakeLists.txt: WAVECAM_EVALUATOR_RERUNS), and every row that runs on a device there too
// where the Vulkan evaluator is built (WAVECAM_GPU_RERUNS), but the kernel summation: its runs on the device are
// checked against the CPU's by GpuSums.KernelSummationRunsMatchTheCpu. A row added to the table
// without its re-runs fails here.
TEST(EvaluatorReruns, EveryRowOfTheTable) {
    auto words = [](const char* list) {
        std::istringstream in(list);
        return std::set<std::string>(std::istream_iterator<std::string>(in), std::istream_iterator<std::string>());
    };
    const std::set<std::string> reruns = words(WAVECAM_EVALUATOR_RERUNS), gpu_reruns = words(WAVECAM_GPU_RERUNS);
    const bool vulkan_built = !gpu_reruns.empty();
    std::set<std::string> rows;
    for (const wavecam::detail::EvaluatorRow& row : wavecam::detail::kEvaluators) {
        rows.insert(row.word);
        EXPECT_EQ(reruns.count(row.word), 1u) << row.word << " has no re-run of the point sums' tests";
        if (vulkan_built && row.device == wavecam::Device::Gpu && row.summation != wavecam::Summation::Kernel) {
            EXPECT_EQ(gpu_reruns.count(row.word), 1u) << row.word << " has no re-run on the device";
        }
    }
    // and nothing re-runs that is not a row
    for (const std::set<std::string>& list : {reruns, gpu_reruns})
        for (const std::string& word : list)
            EXPECT_EQ(rows.count(word), 1u) << word << " is re-run but is no row of the table";
}
