// The kernel summation's runs in direction cosines, where the pinhole is in the Fraunhofer regime.
// Internal to core.
//
// To first order in the pinhole sample ξ, a path from source s through ξ to film point t turns
// by -k (n_s - m_t) . ξ (n_s: the source's direction cosines, m_t: those of the film point's
// pixel ray, docs/physics.md), so the composed sums of a run are
//   U(t) = (f / R_t^2) Σ_ξ H(ξ) e^{i k m_t . ξ} Σ_s w_s e^{-i k n_s . ξ},
//   H(ξ) = (dA(ξ) / λ) e^{i k |ξ|^2 (1/z + 1/f) / 2},
// the wavefronts' curvature kept on the axis, per depth layer (z its planar depth). Where every
// source and film direction lies within a box of width L, a pinhole lattice of pitch λ / L
// serves them all (aperture.h's sampling argument), and on it both sums are Fourier sums: the
// sources' to the lattice a non-uniform FFT of type 1, the lattice's to the film points one of
// type 2 (lattice_nufft.h). A run is then two transforms of about (4 a L / λ)^2 points, whatever
// the field and however wide the PSF, instead of a kernel per field anchor (a 60 deg frame at
// 0.08 mm needs 22 x 22 anchors, and 968 kernels exceed the basis). What is dropped is the
// curvature's change across the field (the film's 1/R_t, the oblique terms (n . ξ)^2 / 2R) and
// its change within a layer; where the rim's whole defocus phase π a^2 (1/z + 1/f) / λ stays
// within kMaxFraunhoferPhase that is at most a few tenths of a radian, and a star's image moves
// by its square. The plan-time check (kernel_error_check.h) compares probe stars with the point
// sums before auto takes it.
//
// The sources are the domain's pixels at their centres, the frame and a margin beyond it where
// the edge is continued, wide enough that a source's PSF leaves kDirectionMarginLight of its
// light beyond it (at most the frame's longer side). The lattice's sums repeat with period L in direction cosines: L spans the
// domain, so a film point's nearest repeat of any source lies beyond the margin.
// Layers: the sources' amplitudes blend linearly between the two nearest, each source's power
// balanced (kernel_summation.h).
#pragma once
#include <complex>
#include <memory>
#include <vector>

#include "convolution/direction_convolution.h"  // kMaxFraunhoferPhase
#include "summation/kernel/kernel_summation.h"

namespace wavecam::detail {

// The light a source's PSF may put beyond the domain's margin (airy_reach).
constexpr double kDirectionMarginLight = 0.01;

// Lattice points across the pinhole, at least: the transfer puts each rim sample on its lattice
// point, not at its open part's centroid, which turns a star's light at direction offset Δ by up to
// π Δ D / (λ modes) (a radian at an Airy radius for 4 points across); where the domain's period
// gives fewer, the period is taken an integer times longer (the domain a part of it).
constexpr int kMinDirectionModes = 128;

// The radius in direction cosines beyond which a disc of the aperture's bounding radius leaves
// `light` of a star's light: 2 λ / (π^2 D r), the Airy pattern's encircled energy far out.
double airy_reach(const Aperture& aperture, double wavelength, double light);

// Whether `spec`'s runs go through directions: coherent runs on the CPU, the nearest source's
// rim phase within kMaxFraunhoferPhase.
bool runs_in_directions(const KernelSummationSpec& spec, const ComputeDevice& device);

// The domain and the lattice of the runs in directions.
struct DirectionGeometry {
    int margin = 0;             // domain pixels beyond the camera frame on every side
    int width = 0, height = 0;  // the domain
    double period = 0;          // L, in direction cosines (both axes)
    int modes = 0;              // lattice points across (both axes), pitch λ / L
    DepthLayers layers;
};
DirectionGeometry direction_geometry(const KernelSummationSpec& spec);

// The pinhole's transfer H on the lattice per depth layer, and what a source's blend of two layers
// takes from it: all a star's field needs (the runs' sources and film points aside).
struct DirectionTransfer {
    DirectionGeometry g;
    std::vector<std::vector<std::complex<float>>> h;  // per layer, modes x modes, centred
    std::vector<double> power, overlap;               // per layer: sum |H_l|^2, Re <H_l, H_l+1>
    // radians per lattice step of direction cosine `cosine`
    double to_step(double cosine) const { return 2 * M_PI * cosine / g.period; }
    // the factor on a source's weight that gives its blend of layers `lower` and `lower` + 1
    // (share `upper` of the latter) the blend of their powers
    double balance(int lower, double upper) const;
};
DirectionTransfer direction_transfer(const KernelSummationSpec& spec);

// A film point (camera pixel position) as the runs read it: radians per lattice step (a type 2
// at minus its direction cosines: the lattice's sum to the film turns by +k m . ξ) and its
// amplitude f / R_t^2 = 1 / (f (1 + u^2 + v^2)).
void place_film_point(const DirectionTransfer& t, const PinholeCamera& c, double x, double y, double& px, double& py,
                      std::complex<float>& weight);

// One unit source's field (unit_sources' source at camera pixel position (x, y), planar inverse
// depth w) at film points given as camera pixel positions: for the plan-time check.
std::vector<std::complex<double>> star_field(const DirectionTransfer& t, const KernelSummationSpec& spec, double x,
                                             double y, double w, const std::vector<double>& film_x,
                                             const std::vector<double>& film_y);

class DirectionRuns {
public:
    DirectionRuns(const KernelSummationSpec& spec, int threads);
    ~DirectionRuns();

    const DirectionGeometry& geometry() const;

    // Per domain pixel, the factor on its weight that gives its blend of two layers the blend of
    // their powers (DirectionTransfer::balance).
    std::vector<float> power_balance(const KernelSummationSources& sources) const;

    // Adds, run by run, scale x the film pixels' irradiance (the mean of |U|^2 over each pixel's
    // n x n points) of camera rows `rows`, columns within the overscan. The runs at once go
    // through the threads, one each; each is added in turn.
    Result<bool> run(const KernelSummationSources& sources, double scale, const RowRange& rows, float* irradiance,
                     const ProgressFn& progress) const;
    int runs_at_once() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

}  // namespace wavecam::detail
