// The exact propagator against the analytic results of docs/physics.md.
// Every expected value below comes from textbook optics computed here, not from wavecam.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "psf_measures.h"
#include "wavecam/propagation.h"
#include "wavecam/psf.h"
#include "summation_flag.h"

using namespace wavecam;
using wavecam::test::azimuthal_profile;
using wavecam::test::centroid_offset;
using wavecam::test::encircled_energy;
using wavecam::test::mean_in_annulus;

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();

PsfImage psf(const PsfParams& p) {
    auto r = compute_psf(p, test_device());
    EXPECT_TRUE(r.ok()) << r.error;
    return r.value;
}

// Number of half-period zones, straight from its definition (docs/physics.md result 1).
double zones(double a, double f, double z, double lambda) {
    const long double A = a, F = f, Z = z;
    const long double film = std::sqrt(F * F + A * A) - F;
    const long double src = std::isinf(z) ? 0.0L : std::sqrt(Z * Z + A * A) - Z;
    return double(2 * (film + src) / lambda);
}

// Irradiance along film points (x, 0), with the lower-level API and a chosen sample pitch.
std::vector<float> line_profile(const Aperture& ap, double f, double lambda, const PointSource& src,
                                const std::vector<double>& xs, double pitch) {
    const ApertureSamples s = sample_aperture(ap, pitch);
    const SummationSettings sum{test_summation(), kSummationTolerance, 0};  // every evaluator in turn (summation_flag.h)
    SummationPlan to_pinhole = SummationPlan::create(test_device(), SumKind::SourcesToPinhole, s, lambda, sum);
    to_pinhole.set_points({src});
    PinholeField field;
    to_pinhole.execute(source_weights({src}), field);
    FilmPoints film;
    film.film_distance = f;
    for (double x : xs) {
        film.x.push_back(static_cast<float>(x));
        film.y.push_back(0.0f);
    }
    std::vector<float> out(xs.size(), 0.0f);
    SummationPlan to_film = SummationPlan::create(test_device(), SumKind::PinholeToFilm, s, lambda, sum);
    to_film.set_points(film);
    to_film.execute_irradiance(field, 1.0 / free_irradiance_at_film_centre(src, f), out.data());
    return out;
}
}  // namespace

// 1. On-axis relative irradiance = 4 sin^2(pi N / 2).
TEST(FresnelZones, OnAxisIrradianceFollowsTheZoneCount) {
    const double f = 50e-3, lambda = 550e-9;
    for (double z : {kInf, 0.2, 0.05}) {
        for (double n_target : {0.3, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0}) {
            // radius giving n_target zones (paraxial), then the exact zone count for that radius
            const double a = std::sqrt(n_target * lambda / (1.0 / f + (std::isinf(z) ? 0.0 : 1.0 / z)));
            const double n = zones(a, f, z, lambda);
            PsfParams p;
            p.summation = test_summation();
            p.aperture = {ApertureShape::Circle, 2 * a};
            p.film_distance = f;
            p.source_distance = z;
            p.wavelength = lambda;
            p.film_size = 1e-6;
            p.resolution = 1;
            const double expected = 4 * std::pow(std::sin(M_PI * n / 2), 2);
            const double got = psf(p).irradiance[0];
            const double tol = std::max(0.01 * expected, 0.01);
            EXPECT_NEAR(got, expected, tol) << "z = " << z << " N = " << n;
        }
    }
}

// 2. Far field (N << 1): first dark ring at 1.22 lambda f / d, 83.8% of the energy inside.
TEST(Airy, FirstDarkRingRadius) {
    const double f = 50e-3, lambda = 550e-9, d = 47e-6;  // N = 0.02
    const double ring = 1.22 * lambda * f / d;
    std::vector<double> xs;
    for (int i = 0; i <= 400; ++i) xs.push_back(1.5 * ring * i / 400);
    const auto prof = line_profile({ApertureShape::Circle, d}, f, lambda, source_at_field_angle(kInf, 0), xs,
                                   sample_pitch(lambda));
    // first local minimum, refined by a parabola through its neighbours
    size_t m = 1;
    while (m + 1 < prof.size() && !(prof[m] <= prof[m - 1] && prof[m] <= prof[m + 1])) ++m;
    ASSERT_LT(m + 1, prof.size());
    const double y0 = prof[m - 1], y1 = prof[m], y2 = prof[m + 1];
    const double shift = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2);
    const double radius = xs[m] + shift * (xs[1] - xs[0]);
    EXPECT_NEAR(radius / ring, 1.0, 0.02);
    EXPECT_LT(prof[m] / prof[0], 1e-3);  // dark
}

TEST(Airy, EncircledEnergyInsideTheFirstRing) {
    PsfParams p;
    p.summation = test_summation();
    p.aperture = {ApertureShape::Circle, 47e-6};
    p.film_distance = 50e-3;
    p.wavelength = 550e-9;
    const double ring = 1.22 * p.wavelength * p.film_distance / p.aperture.diameter;
    p.film_size = 2.4 * ring;
    p.resolution = 161;
    const PsfImage img = psf(p);
    // Total energy on an unbounded film = pinhole area (result 3), in relative-irradiance units.
    const double fraction = encircled_energy(img, ring) / p.aperture.area();
    EXPECT_NEAR(fraction, 0.838, 0.02 * 0.838);
}

// 3. Energy: integral of relative irradiance = pi a^2 (1 + f/z)^2 (paraxial).
TEST(Energy, FilmIntegralEqualsTheGeometricShadowArea) {
    for (double z : {kInf, 0.05}) {
        PsfParams p;
        p.summation = test_summation();
        p.aperture = {ApertureShape::Circle, 0.224e-3};  // N ~ 5 at f = 5 mm, 500 nm
        p.film_distance = 5e-3;
        p.source_distance = z;
        p.wavelength = 500e-9;
        const double shadow = p.aperture.diameter * (1 + (std::isinf(z) ? 0 : p.film_distance / z));
        p.film_size = 3 * shadow;
        p.resolution = 151;
        p.sin_theta_max = std::sin(0.15);  // every film point lies within 0.1 rad of the axis
        const PsfImage img = psf(p);
        const double expected = M_PI * std::pow(shadow / 2, 2);
        EXPECT_NEAR(encircled_energy(img) / expected, 1.0, 0.02) << "z = " << z;
    }
}

// 4. Geometric limit (N >> 1): a uniform disc of diameter d (1 + f/z), ringing at the rim.
TEST(GeometricLimit, LargePinholeCastsItsShadow) {
    for (double z : {kInf, 0.05}) {
        PsfParams p;
        p.summation = test_summation();
        p.aperture = {ApertureShape::Circle, 0.447e-3};  // N ~ 20 at f = 5 mm, 500 nm
        p.film_distance = 5e-3;
        p.source_distance = z;
        p.wavelength = 500e-9;
        const double shadow = p.aperture.diameter * (1 + (std::isinf(z) ? 0 : p.film_distance / z));
        const double R = shadow / 2;
        p.film_size = 1.6 * shadow;
        p.resolution = 161;
        p.sin_theta_max = std::sin(0.15);
        const PsfImage img = psf(p);
        ASSERT_GT(img.fresnel_number, 15);
        // inside: the unobstructed wave (relative irradiance 1), away from the axis spike and rim
        EXPECT_NEAR(mean_in_annulus(img, 0.2 * R, 0.8 * R), 1.0, 0.05) << "z = " << z;
        // outside: dark
        EXPECT_LT(mean_in_annulus(img, 1.2 * R, 1.6 * R), 0.02) << "z = " << z;
        // the edge: the azimuthal profile crosses 1/4 of the free irradiance at the shadow's rim
        // (a straight edge's geometric shadow boundary, Born & Wolf 8.7)
        const double bin = img.pixel_pitch;
        const auto prof = azimuthal_profile(img, bin);
        size_t b = static_cast<size_t>(1.2 * R / bin);
        while (b > 0 && prof[b] < 0.25) --b;
        const double edge = (b + 0.5 + (prof[b] - 0.25) / (prof[b] - prof[b + 1])) * bin;
        EXPECT_NEAR(edge / R, 1.0, 0.02) << "z = " << z;
    }
}

// 4b. Off axis in the geometric limit a plane wave at angle theta casts a disc of the same
// diameter d around -f tan(theta), at the wave's own irradiance: Rayleigh-Sommerfeld I is exact
// for a plane wave over an open plane, so only the obliquity factor makes this come out right.
TEST(GeometricLimit, ObliquePlaneWaveKeepsItsIrradianceInTheShadow) {
    PsfParams p;
    p.summation = test_summation();
    p.aperture = {ApertureShape::Circle, 0.4e-3};  // N ~ 40 at f = 2 mm, 500 nm
    p.film_distance = 2e-3;
    p.wavelength = 500e-9;
    p.source_angle = 40 * M_PI / 180;
    const double R = p.aperture.diameter / 2;
    p.film_size = 3.2 * R;
    p.resolution = 61;
    p.sin_theta_max = 0.8;  // source at 40 deg, film within 43 deg: sin 40 + sin 43 < 2 x 0.8
    const PsfImage img = psf(p);
    EXPECT_NEAR(mean_in_annulus(img, 0.2 * R, 0.8 * R), 1.0, 0.05);
    EXPECT_LT(mean_in_annulus(img, 1.2 * R, 1.6 * R), 0.02);
}

// 5a. Off axis the image is centred on the geometric image point x0 = -f tan(theta).
TEST(OffAxis, CentredOnTheGeometricImage) {
    for (double z : {kInf, 0.3})
        for (double deg : {20.0, 40.0}) {
            PsfParams p;
            p.summation = test_summation();
            p.aperture = {ApertureShape::Circle, 0.2e-3};
            p.film_distance = 20e-3;
            p.source_distance = z;
            p.source_angle = deg * M_PI / 180;
            p.wavelength = 550e-9;
            const double airy = 2.44 * p.wavelength * p.film_distance / p.aperture.diameter;
            p.film_size = 6 * airy / std::pow(std::cos(p.source_angle), 3);
            p.resolution = 81;
            const PsfImage img = psf(p);
            EXPECT_NEAR(img.centre_x, -p.film_distance * std::tan(p.source_angle), 1e-12);
            double dx, dy;
            centroid_offset(img, dx, dy);
            EXPECT_LT(std::fabs(dx), 0.02 * airy) << deg << " deg, z = " << z;
            EXPECT_LT(std::fabs(dy), 0.005 * airy) << deg << " deg, z = " << z;
        }
}

// 5b. Sampling finer than lambda/2 changes the result by < 0.5%.
TEST(Sampling, FinerThanHalfAWavelengthChangesLittle) {
    const double f = 20e-3, lambda = 550e-9;
    const Aperture ap{ApertureShape::Circle, 0.2e-3};
    const PointSource src = source_at_field_angle(0.5, 10 * M_PI / 180);
    double x0, y0;
    geometric_image_point(src, f, x0, y0);
    std::vector<double> xs;
    for (int i = -40; i <= 40; ++i) xs.push_back(x0 + i * 2e-6);
    const auto half = line_profile(ap, f, lambda, src, xs, lambda / 2);
    const auto third = line_profile(ap, f, lambda, src, xs, lambda / 3);
    double peak = 0, worst = 0;
    for (size_t i = 0; i < xs.size(); ++i) peak = std::max(peak, double(third[i]));
    for (size_t i = 0; i < xs.size(); ++i) worst = std::max(worst, std::fabs(half[i] - third[i]) / peak);
    EXPECT_LT(worst, 0.005);
}

TEST(Sampling, NarrowFieldSamplingAgreesWithHalfAWavelength) {
    const double f = 5e-3, lambda = 500e-9;
    const Aperture ap{ApertureShape::Circle, 0.1e-3};
    const PointSource src = source_at_field_angle(kInf, 0);
    std::vector<double> xs;
    for (int i = 0; i <= 60; ++i) xs.push_back(i * 1e-6);
    const auto full = line_profile(ap, f, lambda, src, xs, sample_pitch(lambda));
    const auto narrow = line_profile(ap, f, lambda, src, xs, sample_pitch(lambda, std::sin(0.1)));
    double peak = 0, worst = 0;
    for (size_t i = 0; i < xs.size(); ++i) peak = std::max(peak, double(full[i]));
    for (size_t i = 0; i < xs.size(); ++i) worst = std::max(worst, std::fabs(full[i] - narrow[i]) / peak);
    EXPECT_LT(worst, 0.005);
}

TEST(Validation, HoursOfWorkAreRefusedNamingTheFlag) {
    PsfParams p;
    p.summation = test_summation();
    p.aperture.diameter = 5e-3;
    p.resolution = 2001;
    const auto v = validate(p);
    ASSERT_FALSE(v.ok());
    EXPECT_EQ(v.error.rfind("pinhole:", 0), 0u) << v.error;
    EXPECT_NE(v.error.find("--max-terms"), std::string::npos);
    p = PsfParams{};
    p.summation = test_summation();
    p.film_distance = -1;
    EXPECT_EQ(validate(p).error.rfind("film-distance:", 0), 0u);
}
