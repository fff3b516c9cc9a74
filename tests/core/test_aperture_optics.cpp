// Apertures beyond the disc, against references written here: Fraunhofer sinc^2 for a square,
// a direct 2-D Fourier sum for a polygon, the disc for a rasterised-disc mask, the geometric
// shadow for an L-shaped mask, a radial Rayleigh-Sommerfeld integral for a zone plate, and a
// Rayleigh-Sommerfeld sum over a photon sieve's holes, each integrated on its own grid.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "exact_kernel.h"
#include "psf_measures.h"
#include "wavecam/aperture.h"
#include "wavecam/convolution_method.h"
#include "wavecam/photon_sieve.h"
#include "wavecam/psf.h"
#include "summation_flag.h"

using namespace wavecam;

namespace {

double sinc(double x) { return x == 0 ? 1.0 : std::sin(M_PI * x) / (M_PI * x); }

// Far-field (Fraunhofer) relative irradiance of an aperture for a plane wave at normal incidence
// (Goodman 4.2): U(x) = exp(ikr) / (i lambda r) (f / r) F(x / (lambda r)), F the aperture's 2-D
// Fourier transform, so I = (f / (lambda r^2))^2 |F|^2 relative to the unobstructed plane wave.
double fraunhofer(double f_abs2, double x, double y, double f, double lambda) {
    const double r2 = f * f + x * x + y * y;
    const double s = f / (lambda * r2);
    return s * s * f_abs2;
}

PsfParams far_field(const Aperture& ap) {
    PsfParams p;
    p.summation = test_summation();
    p.aperture = ap;
    p.film_distance = 5e-3;
    p.wavelength = 500e-9;
    p.film_size = 1.2e-3;
    p.resolution = 31;
    return p;
}

}  // namespace

TEST(ApertureOptics, SquareFarFieldIsSincSquared) {
    const double d = 10e-6;  // N = (d/2)^2 / (lambda f) = 0.01: Fraunhofer
    const PsfParams p = far_field({ApertureShape::Square, d});
    auto img = compute_psf(p, test_device());
    ASSERT_TRUE(img.ok()) << img.error;
    double worst = 0, peak = 0;
    for (int j = 0; j < p.resolution; ++j)
        for (int i = 0; i < p.resolution; ++i) {
            double x, y;
            film_position(img.value, i, j, x, y);
            const double r = std::sqrt(p.film_distance * p.film_distance + x * x + y * y);
            // |F| of a square of side d at spatial frequency (x, y) / (lambda r): d^2 sinc sinc
            const double F = d * d * sinc(d * x / (p.wavelength * r)) * sinc(d * y / (p.wavelength * r));
            const double ref = fraunhofer(F * F, x, y, p.film_distance, p.wavelength);
            peak = std::max(peak, ref);
            worst = std::max(worst, std::fabs(img.value.irradiance[size_t(j) * p.resolution + i] - ref));
        }
    EXPECT_LT(worst / peak, 0.01) << "peak " << peak;
}

TEST(ApertureOptics, PolygonFarFieldMatchesADirectFourierSumOfItsShape) {
    // A pentagon turned by 10 degrees: no mirror symmetry about x or y, so a wrong vertex
    // convention or rotation sign shows.
    const double d = 12e-6, R = d / 2, rot = 10 * M_PI / 180;
    const int n = 5;
    const PsfParams p = far_field({ApertureShape::Polygon, d, n, rot});
    auto img = compute_psf(p, test_device());
    ASSERT_TRUE(img.ok()) << img.error;
    // The pentagon rasterised independently: a point is inside when it lies left of every
    // edge from vertex k to vertex k+1 (vertices at rot + 2 pi k / n, counter-clockwise).
    std::vector<double> vx(n), vy(n);
    for (int k = 0; k < n; ++k) {
        vx[k] = R * std::cos(rot + 2 * M_PI * k / n);
        vy[k] = R * std::sin(rot + 2 * M_PI * k / n);
    }
    const int grid = 300;
    const double h = 2 * R / grid;
    std::vector<double> px, py;
    for (int b = 0; b < grid; ++b)
        for (int a = 0; a < grid; ++a) {
            const double x = -R + (a + 0.5) * h, y = -R + (b + 0.5) * h;
            bool in = true;
            for (int k = 0; k < n && in; ++k) {
                const int l = (k + 1) % n;
                in = (vx[l] - vx[k]) * (y - vy[k]) - (vy[l] - vy[k]) * (x - vx[k]) > 0;
            }
            if (in) {
                px.push_back(x);
                py.push_back(y);
            }
        }
    double worst = 0, peak = 0;
    for (int j = 0; j < p.resolution; j += 2)
        for (int i = 0; i < p.resolution; i += 2) {
            double x, y;
            film_position(img.value, i, j, x, y);
            const double r = std::sqrt(p.film_distance * p.film_distance + x * x + y * y);
            // F(u, v) = sum over the open cells of exp(-2 pi i (u xi + v eta)) h^2, (u, v) = (x, y) / (lambda r)
            const double u = x / (p.wavelength * r), v = y / (p.wavelength * r);
            std::complex<double> F = 0;
            for (size_t q = 0; q < px.size(); ++q) F += std::polar(h * h, -2 * M_PI * (u * px[q] + v * py[q]));
            const double ref = fraunhofer(std::norm(F), x, y, p.film_distance, p.wavelength);
            peak = std::max(peak, ref);
            worst = std::max(worst, std::fabs(img.value.irradiance[size_t(j) * p.resolution + i] - ref));
        }
    EXPECT_LT(worst / peak, 0.01) << "peak " << peak;
}

TEST(ApertureOptics, RasterisedDiscMaskMatchesTheCircleInEncircledEnergy) {
    const double d = 0.2e-3;
    PsfParams p;
    p.summation = test_summation();
    p.film_distance = 20e-3;  // N ~ 0.9
    p.wavelength = 550e-9;
    p.film_size = 0.4e-3;
    p.resolution = 61;
    p.sin_theta_max = 0.05;  // every ray within 3 degrees of the axis
    // The disc drawn into a 400 x 400 image, pixel centres inside the circle open.
    const int w = 400;
    std::vector<float> disc(size_t(w) * w);
    for (int r = 0; r < w; ++r)
        for (int c = 0; c < w; ++c) disc[size_t(r) * w + c] = std::hypot(c + 0.5 - 0.5 * w, r + 0.5 - 0.5 * w) < 0.5 * w;
    Aperture mask{ApertureShape::Mask, d};
    mask.mask_file = "disc";
    ASSERT_TRUE(set_aperture_mask(mask, w, w, disc, "aperture").ok());
    p.aperture = mask;
    auto from_mask = compute_psf(p, test_device());
    p.aperture = {ApertureShape::Circle, d};
    auto from_circle = compute_psf(p, test_device());
    ASSERT_TRUE(from_mask.ok() && from_circle.ok());
    const double airy = 1.22 * p.wavelength * p.film_distance / d;
    const double total = M_PI * d * d / 4;
    for (double k : {0.5, 1.0, 1.5, 2.0, 3.0}) {
        const double em = test::encircled_energy(from_mask.value, k * airy);
        const double ec = test::encircled_energy(from_circle.value, k * airy);
        EXPECT_NEAR(em / total, ec / total, 0.01) << k << " Airy radii";
    }
    EXPECT_GT(test::encircled_energy(from_circle.value, airy) / total, 0.5);  // the measure sees the core
}

TEST(ApertureOptics, LShapedMaskBlursAStarIntoAnLRotatedLikeAPrint) {
    // Geometric regime (N ~ 16): the blur of a point at z is the aperture's shadow scaled by
    // (1 + f/z). Mask: an L - the left column and the bottom row of a 2 x 2 image open, the
    // top-right quadrant (x > 0, y > 0 on the pinhole, seen from the film) shut. The upright
    // output, like a real camera's print (the film image turned by 180 degrees), shows the
    // shadow turned by 180 degrees: the shut quadrant at the image's left and bottom.
    const double d = 0.4e-3, f = 5e-3, z = 50e-3;
    Aperture ell{ApertureShape::Mask, d};
    ell.mask_file = "L";
    ASSERT_TRUE(set_aperture_mask(ell, 2, 2, {1, 0, 1, 1}, "aperture").ok());
    PsfParams p;
    p.summation = test_summation();
    p.aperture = ell;
    p.film_distance = f;
    p.source_distance = z;
    p.wavelength = 550e-9;
    p.film_size = 0.8e-3;
    p.resolution = 61;
    p.sin_theta_max = 0.2;
    auto img = compute_psf(p, test_device());
    ASSERT_TRUE(img.ok()) << img.error;
    const int n = p.resolution;
    const double c = 0.5 * (n - 1), half = 0.5 * d * (1 + f / z) / img.value.pixel_pitch;  // shadow half-width, px
    // Energy in each quadrant of the shadow (image left/right, top/bottom), and outside it.
    double quad[2][2] = {{0, 0}, {0, 0}}, outside = 0, all = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double v = img.value.irradiance[size_t(j) * n + i], dx = i - c, dy = j - c;
            all += v;
            if (std::fabs(dx) > half + 1.5 || std::fabs(dy) > half + 1.5) outside += v;
            else if (std::fabs(dx) > 1 && std::fabs(dy) > 1) quad[dx > 0][dy > 0] += v;  // [right][bottom]
        }
    const double shut = quad[0][1];  // image left, bottom
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            if (!(a == 0 && b == 1)) {
                EXPECT_GT(quad[a][b], 8 * shut) << "right " << a << " bottom " << b;
            }
    EXPECT_LT(outside / all, 0.03);  // the blur is the shadow's size, d (1 + f/z)
    // total light = open area (3/4 d^2) x (1 + f/z)^2 (energy result, paraxial)
    const double pixel = img.value.pixel_pitch * img.value.pixel_pitch;
    EXPECT_NEAR(all * pixel / (0.75 * d * d * std::pow(1 + f / z, 2)), 1.0, 0.03);
}

namespace {

// On-axis relative irradiance behind a zone plate for a plane wave (Rayleigh-Sommerfeld I,
// Goodman 3.10): U = 1/(i lambda) * integral over the open zones of exp(i k r) / r * (f / r)
// * 2 pi rho d rho, r = sqrt(f^2 + rho^2); Simpson's rule on each open zone.
double zone_plate_on_axis(double outer_radius, int zones, double f, double lambda) {
    std::complex<double> u = 0;
    const double k = 2 * M_PI / lambda;
    for (int zone = 1; zone <= zones; zone += 2) {
        const double a = outer_radius * std::sqrt((zone - 1.0) / zones), b = outer_radius * std::sqrt(double(zone) / zones);
        const int steps = 4000;
        const double h = (b - a) / steps;
        for (int s = 0; s <= steps; ++s) {
            const double rho = a + s * h, r = std::sqrt(f * f + rho * rho);
            const double w = (s == 0 || s == steps) ? 1 : (s % 2 ? 4 : 2);
            u += w * h / 3 * std::polar(f / (r * r) * 2 * M_PI * rho, k * r);
        }
    }
    u /= std::complex<double>(0, lambda);
    return std::norm(u);
}

double on_axis(const Aperture& ap, double f, double lambda, double sin_theta_max = 1.0) {
    PsfParams p;
    p.summation = test_summation();
    p.aperture = ap;
    p.film_distance = f;
    p.wavelength = lambda;
    p.film_size = 1e-7;
    p.resolution = 1;
    p.sin_theta_max = sin_theta_max;  // 1: cells of lambda / 2, little phase across one (midpoint rule)
    auto img = compute_psf(p, test_device());
    return img.ok() ? img.value.irradiance[0] : NAN;
}

}  // namespace

TEST(ApertureOptics, ZonePlateFocusMatchesARadialRayleighSommerfeldSum) {
    const int zones = 8;
    const double D = 0.4e-3, lambda = 550e-9;
    const Aperture zp{ApertureShape::ZonePlate, D, 0, 0.0, zones};
    const double focus = zone_plate_focus(zp, lambda);
    EXPECT_NEAR(focus, (D / 2) * (D / 2) / zones / lambda, 1e-15);
    const double ref = zone_plate_on_axis(D / 2, zones, focus, lambda);
    EXPECT_GT(ref, 0.8 * 64);  // each open zone adds ~2 to the amplitude: ~(2 x 4)^2 = 64
    EXPECT_NEAR(on_axis(zp, focus, lambda) / ref, 1.0, 0.01);
    // and off focus, where the zones no longer add in phase
    EXPECT_NEAR(on_axis(zp, 0.8 * focus, lambda), zone_plate_on_axis(D / 2, zones, 0.8 * focus, lambda), 0.01 * ref);
}

TEST(ApertureOptics, ZonePlateFocusMovesAsOneOverWavelength) {
    const int zones = 16;
    const double D = 0.4e-3;
    const Aperture zp{ApertureShape::ZonePlate, D, 0, 0.0, zones};
    std::vector<double> best;
    for (double lambda : {450e-9, 650e-9}) {
        // brightest on-axis point over f from 0.85 to 1.15 of r_1^2 / lambda, parabola-refined;
        // coarser cells (lambda / 0.6) scale the irradiance but hardly move its peak
        const double f0 = zone_plate_focus(zp, lambda);
        const int steps = 12;
        std::vector<double> fs, is;
        for (int s = 0; s <= steps; ++s) {
            fs.push_back(f0 * (0.85 + 0.3 * s / steps));
            is.push_back(on_axis(zp, fs.back(), lambda, 0.3));
        }
        const size_t m = std::max_element(is.begin(), is.end()) - is.begin();
        ASSERT_TRUE(m > 0 && m < is.size() - 1);
        const double shift = 0.5 * (is[m - 1] - is[m + 1]) / (is[m - 1] - 2 * is[m] + is[m + 1]);
        best.push_back(fs[m] + shift * (fs[1] - fs[0]));
        EXPECT_NEAR(best.back() / f0, 1.0, 0.03) << lambda;  // at r_1^2 / lambda, less a small focal shift
    }
    EXPECT_NEAR(best[0] / best[1], 650.0 / 450.0, 0.01 * 650 / 450);
}

// The convolution method's pupil takes the mask too, in the same orientation: a star at infinity through
// the L mask (N ~ 15, geometric) lights the shadow's quadrants except the image's left-bottom
// one, as the exact PSF above does.
TEST(ApertureOptics, ConvolutionTurnsTheLMaskLikeTheExactPsf) {
    const double d = 0.4e-3, f = 5e-3;
    Aperture ell{ApertureShape::Mask, d};
    ell.mask_file = "L";
    ASSERT_TRUE(set_aperture_mask(ell, 2, 2, {1, 0, 1, 1}, "aperture").ok());
    const int w = 41, c = w / 2;
    PinholeCamera cam;
    cam.width = cam.height = w;
    cam.fov_h = 2 * std::atan(w * 20e-6 / (2 * f));  // 20 um film pixels: the shadow spans 20
    cam.film_distance = f;
    std::vector<float> rgb(3 * w * w, 0.0f), depth(w * w, 1e10f);  // sky: one depth layer
    for (int k = 0; k < 3; ++k) rgb[3 * (c * w + c) + k] = 1.0f;
    const Matrix3 to709{{{3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}}};
    const auto basis = make_spectral_basis(explicit_sampling({550e-9}).value, to709);
    ASSERT_TRUE(basis.ok());
    std::vector<float> xyz(3 * w * w);
    auto r = diffract_convolution({cam, rgb.data(), depth.data(), DepthMeaning::Planar}, basis.value, ell,
                                  {false, xyz.data()});
    ASSERT_TRUE(r.ok()) << r.error;
    const double half = 0.5 * d / 20e-6;
    double quad[2][2] = {{0, 0}, {0, 0}};
    for (int j = 0; j < w; ++j)
        for (int i = 0; i < w; ++i) {
            const double dx = i - c, dy = j - c;
            if (std::fabs(dx) > 1 && std::fabs(dy) > 1 && std::fabs(dx) < half && std::fabs(dy) < half)
                quad[dx > 0][dy > 0] += xyz[3 * (j * w + i) + 1];  // Y; [right][bottom]
        }
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            if (!(a == 0 && b == 1)) {
                EXPECT_GT(quad[a][b], 8 * quad[0][1]) << "right " << a << " bottom " << b;
            }
}

// ---- Photon sieve ------------------------------------------------------------------------

namespace {

// On-axis relative irradiance behind a set of round holes for a plane wave (Rayleigh-Sommerfeld
// I, Goodman 3.10): U = 1/(i lambda) sum over the holes of the integral of exp(i k r) / r (f / r)
// dA, r = sqrt(f^2 + x^2 + y^2); each hole on its own polar grid (midpoint rule, 96 radii x 192
// angles), independent of the propagators' lattice; the fields summed coherently.
double holes_on_axis(const std::vector<SieveHole>& holes, double f, double lambda) {
    const double k = 2 * M_PI / lambda;
    const int nr = 96, na = 192;
    std::complex<double> u = 0;
    for (const SieveHole& h : holes)
        for (int i = 0; i < nr; ++i) {
            const double s = h.radius * (i + 0.5) / nr, dA = s * (h.radius / nr) * (2 * M_PI / na);
            for (int j = 0; j < na; ++j) {
                const double t = 2 * M_PI * (j + 0.5) / na;
                const double x = h.x + s * std::cos(t), y = h.y + s * std::sin(t);
                const double r = std::sqrt(f * f + x * x + y * y);
                u += std::polar(f / (r * r) * dA, k * r);
            }
        }
    return std::norm(u / std::complex<double>(0, lambda));
}

Aperture parsed(const std::string& text, double diameter) {
    Aperture a = parse_aperture(text, "aperture").value;
    a.diameter = diameter;
    return a;
}

}  // namespace

TEST(ApertureOptics, PhotonSieveFocusMatchesARayleighSommerfeldSumOverItsHoles) {
    const double D = 0.4e-3, lambda = 550e-9;
    const Aperture sieve = parsed("sieve:8", D);
    const double focus = zone_plate_focus(sieve, lambda);  // r_1^2 / lambda = 9.09 mm
    EXPECT_NEAR(focus, (D / 2) * (D / 2) / 8 / lambda, 1e-15);
    const auto holes = sieve_holes(sieve.sieve(), D / 2);
    const double ref = holes_on_axis(holes, focus, lambda);
    // Each ring hole adds about pi a^2 / (lambda f) 2 J1(x) / x, x = pi d / 2w = 3 pi / 4, in
    // phase with the central disc's 2 (the 1.5-width design): the sieve focuses.
    double predicted = 2;
    for (size_t h = 1; h < holes.size(); ++h) {
        const double x = 0.75 * M_PI;
        predicted += M_PI * holes[h].radius * holes[h].radius / (lambda * focus) * 2 * std::cyl_bessel_j(1, x) / x;
    }
    EXPECT_NEAR(ref / (predicted * predicted), 1.0, 0.1) << "reference " << ref << ", estimate " << predicted * predicted;
    const double at_focus = on_axis(sieve, focus, lambda);  // lambda / 2 lattice: 60+ samples per hole
    EXPECT_NEAR(at_focus / ref, 1.0, 0.01) << "propagator " << at_focus << ", reference " << ref;
    // off focus the holes no longer add in phase, and the propagator still follows the reference
    const double off = holes_on_axis(holes, 0.8 * focus, lambda);
    EXPECT_LT(off, 0.3 * ref);
    EXPECT_NEAR(on_axis(sieve, 0.8 * focus, lambda), off, 0.01 * ref);
}

TEST(ApertureOptics, PhotonSieveFocusMovesAsOneOverWavelength) {
    const double D = 0.4e-3;
    const Aperture sieve = parsed("sieve:16", D);
    std::vector<double> best;
    for (double lambda : {450e-9, 650e-9}) {
        // brightest on-axis point over f from 0.85 to 1.15 of r_1^2 / lambda, parabola-refined
        const double f0 = zone_plate_focus(sieve, lambda);
        const int steps = 12;
        std::vector<double> fs, is;
        for (int s = 0; s <= steps; ++s) {
            fs.push_back(f0 * (0.85 + 0.3 * s / steps));
            is.push_back(on_axis(sieve, fs.back(), lambda, 0.3));
        }
        const size_t m = std::max_element(is.begin(), is.end()) - is.begin();
        ASSERT_TRUE(m > 0 && m < is.size() - 1);
        const double shift = 0.5 * (is[m - 1] - is[m + 1]) / (is[m - 1] - 2 * is[m] + is[m + 1]);
        best.push_back(fs[m] + shift * (fs[1] - fs[0]));
        EXPECT_NEAR(best.back() / f0, 1.0, 0.03) << lambda;
    }
    EXPECT_NEAR(best[0] / best[1], 650.0 / 450.0, 0.01 * 650 / 450);
}

// The convolution method takes the sieve (and the zone plate) as its pupil: its kernel at the focus
// against the exact sum, with both of its evaluations. Its matrix transform needs a dozen cells
// across the finest opening: with the 64 it used to take, the focal core came out 6% (sieve)
// and 8% (zone plate) dim.
TEST(ApertureOptics, ConvolutionZonePlateAndSieveKernelsMatchTheExactSum) {
    for (const char* shape : {"sieve:8", "zoneplate:8"}) {
        FieldPsfRequest q;
        q.aperture = parsed(shape, 0.4e-3);
        q.wavelength = 550e-9;
        q.film_distance = zone_plate_focus(q.aperture, q.wavelength);
        q.pixel_pitch = 4e-6;
        q.radius = 12;
        const auto exact = test::exact_kernel(q, 3, 0.3);  // 0.1 is 1.3% off in the core
        for (FieldPsfMethod method : {FieldPsfMethod::MatrixFourier, FieldPsfMethod::TransferFunction}) {
            q.method = method;
            const PsfKernel fast = field_psf_kernel(q);
            for (double r : {0.0, 1.0, 3.0, 12.0})
                EXPECT_NEAR(test::encircled(fast.weight, q.radius, r), test::encircled(exact, q.radius, r),
                            0.02 * test::encircled(exact, q.radius, r))
                    << shape << ", r = " << r << " px, " << (method == FieldPsfMethod::MatrixFourier ? "matrix" : "transfer");
        }
    }
}
