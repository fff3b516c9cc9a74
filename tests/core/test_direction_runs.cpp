// The kernel summation's runs in direction cosines (core/src/summation/kernel/direction_runs.h):
// where they are taken, what their domain holds, and their stars against the point sums' kernels
// through the plan-time check that `auto` consults. Their images against the Rayleigh-Sommerfeld
// integral and their runs against the point sums' same runs: tests/core/test_wide_field.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "summation/kernel/direction_runs.h"
#include "summation/kernel/kernel_error_check.h"
#include "wavecam/scene_diffraction.h"

using namespace wavecam;
using namespace wavecam::detail;

namespace {

KernelSummationSpec spec_of(const PinholeCamera& c, double diameter, double nearest, double wavelength) {
    KernelSummationSpec s;
    s.camera = c;
    s.aperture = {ApertureShape::Circle, diameter};
    s.wavelength = wavelength;
    s.max_inverse_depth = std::isinf(nearest) ? 0.0 : 1 / nearest;
    s.subsamples = 2;
    s.runs = 96;
    s.settings.tolerance = 3e-4;
    return s;
}

double cosine(double u, double v) { return u / std::sqrt(1 + u * u + v * v); }

}  // namespace

// The paper's method at a wide field: a 0.08 mm pinhole at f = 50 mm over 60 deg, sources from
// 0.3 m, is Fraunhofer (its rim's defocus 0.29 rad at 400 nm); the optimum pinhole is not, nor
// incoherent sums, nor a GPU's runs.
TEST(DirectionRuns, TakenWhereThePinholeIsFraunhoferAndTheRunsCoherentOnTheCpu) {
    const PinholeCamera camera{256, 256, 60 * M_PI / 180, 50e-3};
    const ComputeDevice cpu;
    for (double wavelength : {400e-9, 569e-9, 700e-9})
        EXPECT_TRUE(runs_in_directions(spec_of(camera, 0.08e-3, 0.3, wavelength), cpu)) << wavelength;
    EXPECT_FALSE(runs_in_directions(spec_of(camera, 0.315e-3, 0.3, 550e-9), cpu));
    EXPECT_FALSE(runs_in_directions(spec_of(camera, 0.08e-3, 0.05, 550e-9), cpu));  // 0.46 rad
    KernelSummationSpec incoherent = spec_of(camera, 0.08e-3, 0.3, 550e-9);
    incoherent.incoherent = true;
    EXPECT_FALSE(runs_in_directions(incoherent, cpu));
}

// The domain: its margin spans the radius beyond which a star leaves kDirectionMarginLight of its
// light (2 lambda / (pi^2 D r)) along both axes on the domain's outermost row and column, where the
// field compresses pixels most, and the lattice's period spans every source's direction cosine.
TEST(DirectionRuns, TheDomainHoldsAllButOnePercentOfEveryStarsLight) {
    for (double fov : {60.0, 90.0, 120.0}) {
        const PinholeCamera c{160, 96, fov * M_PI / 180, 50e-3};
        const KernelSummationSpec s = spec_of(c, 0.08e-3, INFINITY, 550e-9);
        const DirectionGeometry g = direction_geometry(s);
        const double reach = 2 * 550e-9 / (M_PI * M_PI * 0.08e-3 * kDirectionMarginLight);
        double u_out, v_out, u_in, v_in;
        c.tangent(-g.margin, -g.margin, u_out, v_out);
        c.tangent(0, 0, u_in, v_in);
        EXPECT_GE(std::abs(cosine(u_out, v_out)) - std::abs(cosine(u_in, v_out)), reach * (1 - 1e-9)) << fov;
        EXPECT_GE(std::abs(cosine(v_out, u_out)) - std::abs(cosine(v_in, u_out)), reach * (1 - 1e-9)) << fov;
        EXPECT_EQ(g.width, c.width + 2 * g.margin);
        // every source's direction cosine within half a period of the axis
        double u, v;
        c.tangent(-g.margin + 0.5, c.height / 2.0, u, v);
        EXPECT_LT(std::abs(cosine(u, v)), g.period / 2) << fov;
        // the lattice holds the pinhole: modes x pitch (lambda / period) spans its diameter
        EXPECT_GE(g.modes * 550e-9 / g.period, 0.08e-3) << fov;
        std::printf("%g deg: margin %d px, period %.3f, %d x %d lattice\n", fov, g.margin, g.period, g.modes, g.modes);
    }
}

// A star's image through the runs against the point sums' kernel there (the plan-time check's
// probes: the axis, the left edge's middle and the corner at the nearest depth, and the axis
// midway between the two nearest layers), at 60, 90 and 120 deg: within a fraction of the
// kernel summation's 1.5%, so `auto` takes it for the 60 deg frame.
TEST(DirectionRuns, StarsAreThePointSumsKernelsAndAutoTakesThem) {
    const ComputeDevice cpu;
    for (double fov : {60.0, 90.0, 120.0}) {
        const PinholeCamera camera{fov > 100 ? 96 : 128, fov > 100 ? 96 : 128, fov * M_PI / 180, 50e-3};
        SceneSumSettings s;
        s.aperture = {ApertureShape::Circle, 0.08e-3};
        s.nearest_depth = 0.3;
        s.runs = 96;
        auto check = kernel_error_check(s, cpu, camera, 569e-9);
        ASSERT_TRUE(check.ok()) << check.error;
        ASSERT_EQ(check.value.probes.size(), 4u);
        for (const KernelProbe& p : check.value.probes) {
            std::printf("%g deg, star at (%d, %d)%s: %.3f%% (relative L2 of its pixel image)\n", fov, p.x, p.y,
                        p.layers ? " between layers" : "", 100 * p.error);
            EXPECT_LT(p.error, 0.005) << fov << " deg, (" << p.x << ", " << p.y << ")";
        }
        EXPECT_TRUE(check.value.within());
        if (fov == 60) {
            EXPECT_EQ(chosen_summation(s, cpu, PinholeCamera{256, 256, fov * M_PI / 180, 50e-3}, 569e-9),
                      Summation::Kernel);
        }
    }
}
