// The nufft evaluator (wavecam/summation_plan.h) against the direct sums it stands for: the same
// scene, seed and phases through both evaluators, compared pixel by pixel. Bounds: relative RMS
// <= 1e-3 of the mean, worst pixel <= 1e-2 of the peak.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include "wavecam/psf.h"
#include "wavecam/scene_diffraction.h"
#include "wavecam/summation_plan.h"

using namespace wavecam;

namespace {

struct Difference {
    double rms_over_mean = 0, worst_over_peak = 0;
};

Difference compare(const std::vector<float>& fast, const std::vector<float>& direct) {
    double e = 0, mean = 0, worst = 0, peak = 0;
    for (size_t i = 0; i < direct.size(); ++i) {
        e += double(fast[i] - direct[i]) * (fast[i] - direct[i]);
        mean += direct[i];
        worst = std::max(worst, double(std::fabs(fast[i] - direct[i])));
        peak = std::max(peak, double(direct[i]));
    }
    mean /= direct.size();
    return {std::sqrt(e / direct.size()) / mean, worst / peak};
}

// A textured w x w render: radiance in [0.2, 1], depth cycling through `depths` (inf = sky).
struct Scene {
    PinholeCamera camera;
    std::vector<float> power, depth;
    Scene(int w, double fov, double f, const std::vector<double>& depths) : camera{w, w, fov, f} {
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> u(0.2f, 1.0f);
        for (int p = 0; p < w * w; ++p) {
            power.push_back(u(rng));
            const double d = depths[(p % w / 3 + p / w / 5) % depths.size()];
            depth.push_back(std::isinf(d) ? 1e10f : float(d));
        }
    }
    // On the CPU, noting what ran in `report` where one is given.
    std::vector<float> diffract(SceneSumSettings s, Summation how, double lambda, SumReport* report = nullptr) const {
        s.summation = how;
        std::vector<float> out(power.size(), 0.0f);
        auto r = diffract_monochrome({camera, power.data(), depth.data()}, lambda, s, ComputeDevice{}, out.data(), {},
                                     report);
        EXPECT_TRUE(r.ok()) << r.error;
        return out;
    }
};

// Settings asking for `summation`, the rest their defaults.
SummationSettings asking(Summation summation) {
    SummationSettings s;
    s.summation = summation;
    return s;
}

void expect_agreement(const Difference& d, const char* what) {
    std::printf("%s: fast vs direct relative RMS %.3g of the mean, worst %.3g of the peak\n", what, d.rms_over_mean,
                d.worst_over_peak);
    EXPECT_LE(d.rms_over_mean, 1e-3) << what;
    EXPECT_LE(d.worst_over_peak, 1e-2) << what;
}

}  // namespace

// 0.3 mm at f = 50 mm, 64 x 64 over 30 degrees, sources at 0.3 m, 2 m and sky; one run.
TEST(NufftSummation, MatchesTheDirectSumsAtPointThreeMillimetres) {
    const Scene scene(64, 30 * M_PI / 180, 50e-3, {0.3, 2.0, INFINITY});
    SceneSumSettings s;
    s.aperture = {ApertureShape::Circle, 0.3e-3};
    s.runs = 1;
    s.film_subsamples = 2;
    expect_agreement(compare(scene.diffract(s, Summation::Nufft, 550e-9), scene.diffract(s, Summation::Direct, 550e-9)),
                     "0.3 mm, 64x64, 30 deg");
}

// 1 mm at f = 50 mm, 24 x 24 over 10 degrees (24 rather than 32 keeps the direct reference quick) (Fresnel number ~ 9 at the film): the chirps vary by
// tens of radians over the pinhole, so the interpolation needs its most nodes here.
TEST(NufftSummation, MatchesTheDirectSumsAtOneMillimetre) {
    const Scene scene(24, 10 * M_PI / 180, 50e-3, {0.3, 2.0, INFINITY});
    SceneSumSettings s;
    s.aperture = {ApertureShape::Circle, 1e-3};
    s.runs = 1;
    s.film_subsamples = 2;
    expect_agreement(compare(scene.diffract(s, Summation::Nufft, 550e-9), scene.diffract(s, Summation::Direct, 550e-9)),
                     "1 mm, 24x24, 10 deg");
}

// A point source 40 degrees off axis through 0.08 mm, finite and at infinity: the PSF both ways.
TEST(NufftSummation, MatchesTheDirectSumsForAnOffAxisPsf) {
    for (double distance : {0.5, double(INFINITY)}) {
        PsfParams p;
        p.aperture = {ApertureShape::Circle, 0.08e-3};
        p.film_distance = 20e-3;
        p.source_distance = distance;
        p.source_angle = 40 * M_PI / 180;
        p.film_size = 0.8e-3;
        p.resolution = 129;
        p.summation = Summation::Direct;
        auto direct = compute_psf(p, ComputeDevice{});
        p.summation = Summation::Nufft;
        auto fast = compute_psf(p, ComputeDevice{});
        ASSERT_TRUE(direct.ok() && fast.ok());
        expect_agreement(compare(fast.value.irradiance, direct.value.irradiance),
                         std::isinf(distance) ? "0.08 mm PSF, 40 deg, plane wave" : "0.08 mm PSF, 40 deg, 0.5 m");
    }
}

// The random-phase sum with jitter and many runs is a sum of single runs: both evaluators agree
// run by run, so the K-run image agrees too; and Fast (the default) takes the NUFFTs here.
TEST(NufftSummation, TheDefaultTakesTheNufftsWhereTheyAreCheaper) {
    const Scene scene(48, 40 * M_PI / 180, 50e-3, {0.5, INFINITY});
    SceneSumSettings s;
    s.aperture = {ApertureShape::Circle, 0.2e-3};
    s.runs = 2;
    s.film_subsamples = 2;
    s.jitter = true;
    s.summation = Summation::Auto;
    const double fast_work = scene_terms(s, ComputeDevice{}, scene.camera, 550e-9);
    s.summation = Summation::Direct;
    const double direct_work = scene_terms(s, ComputeDevice{}, scene.camera, 550e-9);
    std::printf("48x48, 0.2 mm, 2 runs: work %.3g direct terms (fast) vs %.3g (direct)\n", fast_work, direct_work);
    EXPECT_LT(fast_work, direct_work / 2);  // measured: 4x less
    expect_agreement(compare(scene.diffract(s, Summation::Auto, 600e-9), scene.diffract(s, Summation::Direct, 600e-9)),
                     "48x48, 0.2 mm, 2 runs, jitter");
}

// Every division of the pinhole into sub-apertures (1, 2, 4, 8 per side), each sum against the
// direct one: 300 sources within 20 degrees at 0.3 m, 2 m and at infinity, 0.3 mm, to a 40 x 40
// film at 50 mm. At the scene pitch for 30 degrees (lambda / (2 sin 30)) the frequencies fill
// 68% of the band and the rim samples go through the stencil at its loosest; at lambda / 2, 34%;
// at lambda / (2 x 0.36), 95%: beyond the stencil's reach (90%), so the outermost tenth of the
// sources and film points take the direct terms for the rim, the rest the stencil.
TEST(NufftSummation, EveryDivisionIntoSubAperturesMatchesTheDirectSums) {
    const double lambda = 550e-9, f = 50e-3, spread = std::sin(20 * M_PI / 180);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> u(-spread, spread), ph(0, 2 * M_PI);
    std::vector<PointSource> sources;
    const double depths[] = {0.3, 2.0, INFINITY};
    for (int s = 0; s < 300; ++s) {
        const double ux = u(rng), uy = u(rng), uz = std::sqrt(1 - ux * ux - uy * uy), d = depths[s % 3];
        PointSource p;
        p.at_infinity = std::isinf(d);
        const double r = p.at_infinity ? 1.0 : d;
        p.x = r * ux, p.y = r * uy, p.z = r * uz;
        p.phase = ph(rng);
        sources.push_back(p);
    }
    FilmPoints film;
    film.film_distance = f;
    for (int j = 0; j < 40; ++j)
        for (int i = 0; i < 40; ++i) {
            film.x.push_back(float(f * std::tan(20 * M_PI / 180) * (i - 19.5) / 19.5));
            film.y.push_back(float(f * std::tan(20 * M_PI / 180) * (j - 19.5) / 19.5));
        }
    for (double sin_max : {0.5, 1.0, 0.36}) {
        const ApertureSamples samples = sample_aperture({ApertureShape::Circle, 0.3e-3}, sample_pitch(lambda, sin_max));
        PinholeField direct;
        ASSERT_TRUE(illuminate_pinhole(samples, sources, lambda, direct, 0));
        std::vector<std::complex<double>> film_direct(film.size());
        ASSERT_TRUE(add_film_field({samples, direct, film, lambda}, film_direct.data(), 0));
        for (int blocks : {1, 2, 4, 8}) {
            PlanScope scope;  // the nufft evaluator with this division, as a job passes its choice to shares
            scope.fixed_choice = true;
            scope.choice.evaluator = Evaluator::Nufft;
            scope.choice.blocks = blocks;
            SummationPlan to_pinhole = SummationPlan::create(ComputeDevice{}, SumKind::SourcesToPinhole, samples, lambda, {}, scope);
            to_pinhole.set_points(sources);
            PinholeField fast;
            ASSERT_TRUE(to_pinhole.execute(source_weights(sources), fast).ok());
            double e = 0, n = 0;
            for (size_t j = 0; j < samples.size(); ++j) {
                e += std::norm(std::complex<double>(fast.re[j] - direct.re[j], fast.im[j] - direct.im[j]));
                n += std::norm(std::complex<double>(direct.re[j], direct.im[j]));
            }
            const double pinhole_error = std::sqrt(e / n);
            std::vector<std::complex<double>> film_fast(film.size());
            SummationPlan to_film = SummationPlan::create(ComputeDevice{}, SumKind::PinholeToFilm, samples, lambda, {}, scope);
            to_film.set_points(film);
            ASSERT_TRUE(to_film.execute(direct, film_fast.data()).ok());
            e = n = 0;
            for (size_t t = 0; t < film.size(); ++t) e += std::norm(film_fast[t] - film_direct[t]), n += std::norm(film_direct[t]);
            const double film_error = std::sqrt(e / n);
            std::printf("pitch lambda/(2 x %.2f), %d x %d sub-apertures: relative RMS field error, pinhole %.3g, film %.3g\n",
                        sin_max, blocks, blocks, pinhole_error, film_error);
            EXPECT_LT(pinhole_error, 1e-3) << blocks;
            EXPECT_LT(film_error, 1e-3) << blocks;
        }
    }
}

// A plan is committed once and executed for many weight vectors (the runs): each execute gives
// what a plan made afresh for those weights gives, to the bit, through either evaluator; and the
// evaluator it runs is the one choose_sum picks for its counts.
TEST(SummationPlan, ExecutesManyTimesAsFreshPlansDo) {
    const double lambda = 550e-9, f = 30e-3;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-0.2, 0.2), ph(0, 2 * M_PI);
    std::vector<PointSource> sources(200);
    for (PointSource& p : sources) {
        const double ux = u(rng), uy = u(rng);
        p.x = ux, p.y = uy, p.z = std::sqrt(1 - ux * ux - uy * uy);
        p.amplitude = 0.5 + u(rng);
    }
    FilmPoints film;
    film.film_distance = f;
    for (int t = 0; t < 300; ++t) film.x.push_back(float(f * u(rng))), film.y.push_back(float(f * u(rng)));
    const ApertureSamples samples = sample_aperture({ApertureShape::Circle, 0.25e-3}, sample_pitch(lambda, 0.5));
    for (Summation asked : {Summation::Direct, Summation::Nufft}) {
        SummationPlan kept = SummationPlan::create(ComputeDevice{}, SumKind::SourcesToPinhole, samples, lambda, asking(asked));
        kept.set_points(sources);
        SummationPlan to_film = SummationPlan::create(ComputeDevice{}, SumKind::PinholeToFilm, samples, lambda, asking(asked));
        to_film.set_points(film);
        EXPECT_EQ(kept.choice().evaluator, asked == Summation::Nufft ? Evaluator::Nufft : Evaluator::Direct);
        for (int run = 0; run < 3; ++run) {
            for (PointSource& p : sources) p.phase = ph(rng);
            SummationPlan fresh = SummationPlan::create(ComputeDevice{}, SumKind::SourcesToPinhole, samples, lambda, asking(asked));
            fresh.set_points(sources);
            PinholeField a, b;
            ASSERT_TRUE(kept.execute(source_weights(sources), a).ok());
            ASSERT_TRUE(fresh.execute(source_weights(sources), b).ok());
            EXPECT_EQ(a.re, b.re) << summation_word(asked) << " run " << run;
            EXPECT_EQ(a.im, b.im) << summation_word(asked) << " run " << run;
            std::vector<std::complex<double>> ua(film.size()), ub(film.size());
            SummationPlan fresh_film = SummationPlan::create(ComputeDevice{}, SumKind::PinholeToFilm, samples, lambda, asking(asked));
            fresh_film.set_points(film);
            ASSERT_TRUE(to_film.execute(a, ua.data()).ok());
            ASSERT_TRUE(fresh_film.execute(a, ub.data()).ok());
            EXPECT_EQ(ua, ub) << summation_word(asked) << " run " << run;
        }
    }
    // auto: the cheaper by the cost model, recorded in the plan's choice
    SummationPlan chosen = SummationPlan::create(ComputeDevice{}, SumKind::PinholeToFilm, samples, lambda, asking(Summation::Auto));
    chosen.set_points(film);
    const SumChoice& c = chosen.choice();
    EXPECT_EQ(c.evaluator, c.nufft_work < c.direct_work ? Evaluator::Nufft : Evaluator::Direct);
    EXPECT_EQ(c.work, std::min(c.nufft_work, c.direct_work));
    EXPECT_GT(c.direct_work, 0);
}

// What the output's header names under `auto`: one word where every sum took one evaluator, each
// sum's where they differ, never a choice left open.
TEST(SummationPlan, EvaluatorsAreNamedOneByOne) {
    auto set = [](bool dp, bool np, bool df, bool nf) {
        EvaluatorSet e;
        if (dp) e.add(false, Evaluator::Direct);
        if (np) e.add(false, Evaluator::Nufft);
        if (df) e.add(true, Evaluator::Direct);
        if (nf) e.add(true, Evaluator::Nufft);
        return e;
    };
    auto words = [&](bool dp, bool np, bool df, bool nf) { return set(dp, np, df, nf).words(); };
    EXPECT_EQ(words(true, false, true, false), "direct");
    EXPECT_EQ(words(false, true, false, true), "nufft");
    EXPECT_EQ(words(true, false, false, true), "direct to the pinhole, nufft to the film");
    EXPECT_EQ(words(false, true, true, false), "nufft to the pinhole, direct to the film");
    EXPECT_EQ(words(true, true, true, false), "direct and nufft to the pinhole, direct to the film");
    EXPECT_EQ(words(false, false, false, true), "nufft");  // no sources: only the film's sum ran
    EXPECT_EQ(words(false, false, false, false), "");
    EvaluatorSet a = set(true, false, true, false);
    a.add(set(false, true, false, false));
    EXPECT_EQ(a.words(), "direct and nufft to the pinhole, direct to the film");
}

// A job's report notes what its sums committed (the header's evaluators and device), as they run;
// nothing is kept on the device handle, which a host may share between jobs.
TEST(SumReport, TheJobsReportRecordsTheEvaluatorsThatRan) {
    const Scene scene(8, 20 * M_PI / 180, 50e-3, {2.0});
    SceneSumSettings s;
    s.aperture = {ApertureShape::Circle, 0.2e-3};
    s.runs = 1;
    s.film_subsamples = 1;
    SumReport report;
    EXPECT_EQ(report.evaluators().words(), "");
    EXPECT_EQ(report.ran_on(ComputeDevice{}), "cpu");
    scene.diffract(s, Summation::Direct, 550e-9, &report);
    EXPECT_EQ(report.evaluators().words(), "direct");
    scene.diffract(s, Summation::Nufft, 550e-9, &report);
    EXPECT_EQ(report.evaluators().words(), "direct and nufft");
    EXPECT_EQ(report.ran_on(ComputeDevice{}), "cpu");
}

// auto weighs the NUFFTs by planning their chirp's boxes, which runs on one thread: over a wide
// field the plan alone can outweigh the direct terms many times (a 32 px frame at 120 deg planned
// for more than ten minutes against four of direct terms). Planning stops once it would cost a
// quarter of the direct terms, and auto takes those (an asked nufft is planned to the end).
TEST(SummationPlan, AutoStopsPlanningWhereThePlanOutweighsTheDirectTerms) {
    const double lambda = 550e-9, f = 10e-3, tan_half = std::tan(60 * M_PI / 180);
    const ApertureSamples samples = sample_aperture({ApertureShape::Circle, 0.041e-3}, sample_pitch(lambda, 1.0));
    auto film_of = [&](int side) {
        FilmPoints film;
        film.film_distance = f;
        for (int j = 0; j < side; ++j)
            for (int i = 0; i < side; ++i) {
                film.x.push_back(float(f * tan_half * (2.0 * (i + 0.5) / side - 1)));
                film.y.push_back(float(f * tan_half * (2.0 * (j + 0.5) / side - 1)));
            }
        return film;
    };
    SummationPlan few = SummationPlan::create(ComputeDevice{}, SumKind::PinholeToFilm, samples, lambda, asking(Summation::Auto));
    ASSERT_TRUE(few.set_points(film_of(8)).ok());
    EXPECT_EQ(few.choice().evaluator, Evaluator::Direct);
    EXPECT_TRUE(std::isinf(few.choice().nufft_work)) << few.choice().nufft_work;
    EXPECT_EQ(few.choice().work, few.choice().direct_work);
    // a narrow field's many points: the plan costs little beside their direct terms, and is weighed
    SummationPlan narrow = SummationPlan::create(ComputeDevice{}, SumKind::PinholeToFilm, samples, lambda, asking(Summation::Auto));
    FilmPoints film = film_of(64);
    for (float& x : film.x) x *= 0.1f;
    for (float& y : film.y) y *= 0.1f;
    ASSERT_TRUE(narrow.set_points(film).ok());
    EXPECT_TRUE(std::isfinite(narrow.choice().nufft_work)) << narrow.choice().nufft_work;
}

// A job decides once (decide_summation): each point sum's evaluator at each wavelength, from the
// same counts the estimate prices, and every wavelength's sums follow it; nothing below decides
// again. Shown by a decision that differs from what the frame alone would take: a 4 x 4 frame
// takes the direct terms for both sums, and the job's sums follow a decision of nufft for the
// film, whose image then matches the direct one within the nufft's tolerance.
TEST(SummationDecision, TheJobDecidesOnceAndItsSumsFollow) {
    const Scene scene(4, 20 * M_PI / 180, 50e-3, {2.0});
    const double lambda = 550e-9;
    SceneSumSettings s;
    s.aperture = {ApertureShape::Circle, 0.2e-3};
    s.runs = 1;
    s.film_subsamples = 1;
    s.nearest_depth = 2.0;
    s.jitter = true;  // (the kernel summation does not apply: the point sums' choices are the decision)
    const SummationDecision d = decide_summation(s, ComputeDevice{}, scene.camera, {450e-9, lambda, 650e-9});
    ASSERT_EQ(d.summation, Summation::Auto);
    ASSERT_EQ(d.choices.size(), 3u);
    for (const double w : {450e-9, lambda, 650e-9}) {
        ASSERT_NE(d.to_pinhole_at(w), nullptr);
        // the decision is the estimate's: the same counts through the same chooser
        const EvaluatorSet e = scene_evaluators(s, ComputeDevice{}, scene.camera, w);
        EXPECT_TRUE(e.has(false, d.to_pinhole_at(w)->evaluator));
        EXPECT_TRUE(e.has(true, d.to_film_at(w)->evaluator));
    }
    EXPECT_EQ(d.to_pinhole_at(500e-9), nullptr);  // a wavelength it did not decide
    ASSERT_EQ(d.to_film_at(lambda)->evaluator, Evaluator::Direct);

    // alone, the frame takes what the decision says; told nufft for the film, its sums take that
    SumReport alone;
    const std::vector<float> direct = scene.diffract(s, Summation::Auto, lambda, &alone);
    EXPECT_EQ(alone.evaluators().words(), "direct");
    SummationDecision told = d;
    told.choices[1].to_film.evaluator = Evaluator::Nufft;
    told.choices[1].to_film.blocks = 1;
    SumReport followed;
    s.decision = std::make_shared<SummationDecision>(told);
    const std::vector<float> decided = scene.diffract(s, Summation::Auto, lambda, &followed);
    EXPECT_EQ(followed.evaluators().words(), "direct to the pinhole, nufft to the film");
    const Difference diff = compare(decided, direct);
    EXPECT_LE(diff.worst_over_peak, 1e-3);
}
