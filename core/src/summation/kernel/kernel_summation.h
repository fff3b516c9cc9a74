// The scene-sum methods' runs as convolutions with amplitude PSFs: the `kernel` summation
// (docs/summation.md, "The runs as convolutions"). Internal to core.
//
// The two sums composed carry a source s to a film point t through
//   T(t, s) = sum_xi [exp(i k (r_s - |P_s|)) / r_s] [exp(i k (r_t - |T_t|)) f / r_t^2] dA / lambda,
// both phases measured from the pinhole's centre (summation_plan.h). To second order in the
// pinhole coordinate xi (fresnel_psf.h) it depends on t only through t's offset from s's
// geometric image, stretched with the field angle, and on s only through that field angle and
// its defocus 1/z + 1/f: a shift-invariant amplitude PSF per depth and field. One run,
//   U(t) = sum_s w_s T(t, s),
// is then a convolution of the sources' complex weights with complex kernels, which the runs'
// random phases leave alone: the convolution method's machinery (anchored_convolution.h) with
// amplitudes instead of powers, |U|^2 taken after the sum.
//
// Kernels. Each is the point sums themselves (summation_plan.h, `auto`) from one source at a
// field anchor and a depth layer to the film points of the (2 R + 1)^2 pixels round its image:
// the same lattice, film points, amplitudes and obliquity as the direct sums, so a source at an
// anchor on a layer gets its exact image; elsewhere the kernel is blended, as the convolution
// method blends its intensities, per source: bilinearly over the four anchors round it,
// linearly in 1/z between its two layers. Layers lie evenly in 1/z with the defocus phase
// pi a^2 dw / lambda at most kMaxLayerPhase between neighbours, so a blend of two amplitudes
// stays within (0.3)^2 / 8 of the kernel between them; beyond kMaxKernelLayers the scene's depth
// range is refused (large pinholes over deep scenes: the direct or nufft sums serve them).
//
// Energy. Amplitudes blended over anchors whose kernels differ (wider off axis, 1/cos^3
// radially) carry less power than the same blend of their powers: |sum phi_a K_a|^2 sums to
// sum phi_a phi_b Re<K_a, K_b> <= sum phi_a |K_a|^2 (a wall at 50 deg, 48 px, lost 9% midway
// between anchors). Each source's weight is scaled so that its blended kernel carries the blend
// of its kernels' powers, as the intensity blend of the convolution method and of the
// incoherent case does; the image's shape within a pixel stays the amplitudes' blend.
//
// The blend's mean. Balanced, the amplitude blend still puts its power in the wrong place: the
// rings of neighbouring anchors' kernels, stretched differently by the field, meet out of phase
// and cancel, and the balance moves their light into the core. The cancelled share grows with
// the cell's width (the rings decorrelate beyond a radius that shrinks as the cells grow), so a
// star between the outermost anchors of the 128 x 128 bench frame at 50 deg (a PSF of a third of
// a pixel, cells 19 px) came out 5.5% too bright in its pixel, its ring pixels too dark; blending
// the kernels' pixel images instead errs by 0.2-0.3% there. Over the runs, whose random phases
// average the cross terms of different sources away, the mean of |sum_s w_s K_s|^2 is
// sum_s P_s b_s^2 |K_blend,s|^2 (P the source's power, b its balance). Across anchors the
// intensities blend right, across layers the amplitudes do (neighbouring layers are within
// kMaxLayerPhase of defocus, and blending their intensities washes out the Fresnel zones: a source
// at 5 cm between two layers came out 7.7% too bright on the axis). The mean is brought to
//   T = sum_a phi_a beta_a |L_a|^2,   L_a = sum_l lambda_l K_la,
// the anchors' intensity blend of each anchor's layer blend (beta_a its balance over its layers,
// phi_a the anchor's weight, lambda_l the layers'). With kernel weights w_u = phi_a lambda_l, I_u
// each kernel's pixel image (each pixel's mean of |K_u|^2 over its film points), J_uv that of
// |K_u - K_v|^2 and |sum_u w_u K_u|^2 = sum_u w_u I_u - sum_{u<v} w_u w_v J_uv (sum w = 1), the
// difference added to every run's mean (as the far tail is) is, per source,
//   P [sum_u w_u (beta_a(u) - b^2) I_u + sum_{u<v} (b^2 w_u w_v - [a(u) = a(v)] beta_a w_u w_v / phi_a) J_uv].
// Each run keeps the amplitudes' blend (its speckle); the job's mean is T: the star above 0.14%
// from the point sums' image.
//
// The far tail. A kernel holds kPsfKernelEnergy of its PSF's power; what lies beyond it is added
// to the runs' mean as the convolution method adds it (far_tail.h): each source's missing share,
// from the Fresnel PSF of the same radius (fresnel_psf.h), spread over the annulus beyond the
// kernel. Its cross terms with other sources have random phases and average out over the runs,
// but slowly: the runs then differ from the point sums' same runs by about 0.8 sqrt(t / K) RMS
// of the mean, t the share left out, K the coded runs (a textured two-depth frame, a 2 px PSF,
// t = 3%: 3.3%, 1.75%, 0.96% at K = 16, 64, 256 at 10 deg, 1.53% at 64 at 60 deg; the incoherent
// sums, the runs' limit, 0.25%). So coherent runs of a job of few runs take kernels that hold
// more (kernel_energy): t = kFewRunsDeficit up to 64 runs, rising to kPsfKernelEnergy's 3% at
// 128; 1.37% then at 64 runs at 10 deg. Not where the Airy radius is under a pixel: on a uniform
// wall at 50 deg with a PSF of half a pixel the runs differed from the point sums' by 1.03% with
// t = 3% and 1.10% with 1.5%, at five times the kernels' work.
//
// A few transforms per run. The kernels of neighbouring anchors and layers are much alike: as
// combinations of a few basis kernels (kernel_basis.h, each kernel within kBasisTolerance of its
// power; 31 for 75 kernels of a 128 x 128 frame at 50 deg over three layers), a run transforms
// one image per basis kernel, each source weighted by its blend's coefficients, instead of one
// per anchor and layer.
//
// Incoherent (the random phases' limit): the same kernels' powers |T|^2 convolve the sources'
// powers, blended the same way.
#pragma once
#include <complex>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "convolution/kernel_table.h"
#include "wavecam/scene_diffraction.h"
#include "wavecam/summation_plan.h"

namespace wavecam::detail {

constexpr double kMaxLayerPhase = 0.3;
// Anchor cells at least this many kernel radii wide (the convolution method's kMinCellRadii is
// 6): amplitudes of neighbouring anchors blend less well than powers, so anchors lie closer. A
// source between the corner anchors of a 24 px frame at 50 deg (f = 2 mm, 0.05 mm, R = 9) got 95%
// of its exact peak at cells of 6 R, 99-101% at 2 R.
constexpr int kMinAmplitudeCellRadii = 2;
constexpr int kMaxKernelLayers = 32;
constexpr int kMaxRunsAtOnce = 8;
// What a coherent run's kernels leave out of their PSF at 64 runs or fewer (the far tail above).
constexpr double kFewRunsDeficit = 0.015;

// Depth layers for amplitude kernels at one wavelength: even in 1/z from the sky (0) to the
// nearest source, kMaxLayerPhase apart in defocus phase (one layer where the whole range is
// within it). count > kMaxKernelLayers: the range needs more than the evaluator takes.
DepthLayers amplitude_layers(double max_inverse_depth, double aperture_radius, double wavelength);
// The refusal when they are more: names the setting `summation`.
Result<bool> too_many_layers();

struct KernelSummationSpec {
    PinholeCamera camera;
    int overscan = 0;
    Aperture aperture{ApertureShape::Circle, 0.0};
    double wavelength = 0;
    double max_inverse_depth = 0;  // planar 1/z of the nearest source (0: all sky)
    int subsamples = 1;            // n x n film points per pixel, as the direct sums place them
    int anchor_cells = 4;          // field-anchor cells across the frame's long side
    bool incoherent = false;       // powers through |T|^2 instead of amplitudes through T
    int runs = 1;                  // the job's coherent runs: few take kernels that hold more
    SummationSettings settings;    // how the kernels' sums are evaluated
};

// The source a kernel starts from: unit power at image position (x, y) (camera pixels), at planar
// inverse depth w (0: a plane wave), as the point sums place a source.
using UnitSource = std::function<PointSource(double x, double y, double inverse_depth)>;

// The sources on the convolution's domain (the output frame widened by the kernel radius on
// every side), row-major: complex weights (coherent) or powers in .real() (incoherent), and each
// pixel's layer and the share of it that goes to the layer above.
struct KernelSummationSources {
    int runs = 1;  // runs at once: `weight` holds runs x the domain's pixels, run by run
    std::vector<std::complex<float>> weight;
    std::vector<uint8_t> lower;
    std::vector<float> upper_share;
};

// Camera rows [begin, end): a share's rows of the film.
struct RowRange {
    int begin, end;
};

class KernelSummation {
public:
    KernelSummation();
    ~KernelSummation();
    KernelSummation(KernelSummation&&) noexcept;
    KernelSummation& operator=(KernelSummation&&) noexcept;

    // Kernels from the point sums on the pinhole lattice of `lattice_pitch` (kernel_lattice_pitch)
    // and their spectra, on `device` (its runs there where it can hold them: on_gpu); fails when
    // cancelled, or where the depth range needs more than kMaxKernelLayers layers.
    static Result<KernelSummation> create(const ComputeDevice& device, const KernelSummationSpec& spec,
                                          double lattice_pitch, const UnitSource& unit_source,
                                          const ProgressFn& progress);
    bool on_gpu() const;  // the runs on the device's GPU (else on the CPU)

    int radius() const;
    int domain_width() const;
    int domain_height() const;
    // Domain pixel (i, j) is camera pixel (i - origin, j - origin).
    int origin() const;
    const DepthLayers& layers() const;

    // Adds, run by run, scale x the film pixels' irradiance (the mean of |U|^2 over each pixel's
    // n x n points) of camera rows `rows`, columns within the overscan, and then
    // scale x `each` (camera width x height; may be null) to irradiance (camera width x height).
    // The runs at once share each pass over the kernels' spectra. Fails only when cancelled
    // through `progress`, or on the device.
    Result<bool> run(const KernelSummationSources& sources, double scale, const RowRange& rows, const float* each,
                     float* irradiance, const ProgressFn& progress) const;
    // How many runs to give run() at once: as many as keep their work buffers within the
    // spectra's size (a run's pass over them streams them all), at least 1, at most
    // kMaxRunsAtOnce.
    int runs_at_once() const;

    // Per domain pixel, the factor on its weight that gives its blended kernel the blend of its
    // kernels' powers (1 for the incoherent case).
    std::vector<float> power_balance(const KernelSummationSources& sources) const;

    // Adds to `each` (camera width x height; rows `rows`, columns within the overscan) what the
    // runs' mean lacks of T (the blend's mean, above), per domain pixel round it. `power` (before
    // the balance) and `balance` (power_balance's factors) per domain pixel.
    void add_blend_mean(const KernelSummationSources& sources, const std::vector<float>& power,
                        const std::vector<float>& balance, const RowRange& rows, float* each) const;

    // Adds scale x the far tail of the scene (radiance and depth per camera pixel, the edge
    // continued beyond) on the same rows.
    void add_far_tail(const float* radiance, const float* depth, DepthMeaning meaning, double scale,
                      const RowRange& rows, float* irradiance) const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

// The kernels' pinhole lattice. A kernel's phases are measured from the pinhole's centre, so its
// sum over the pinhole turns, along each axis, only at k (d_s + d_t) (d: the unit directions from
// the centre to its source and to a film point; 0 at the source's geometric image) plus the
// wavefronts' curvature, k a (1/|P_s| + 1/|T_t|) at the rim: slowly for film points near the
// image, where the frame's sums must serve every source and film point at once. A square lattice
// of pitch h repeats a kernel's field at direction shifts of lambda / h along each axis (the
// frame's own condition, lattice_pitch in scene_sum.cpp); at kKernelLatticeMargin times
// the kernels' widest turn, their core's width lambda / D added, the repeats of every kernel's
// core lie kKernelLatticeMargin - 1 kernel widths beyond it, and what falls on the kernel is
// the far tail's (docs/summation.md gives the error against the frame's lattice). Never coarser
// than d / kMinSamplesAcross (the rim resolved as a quadrature), never finer than
// `frame_pitch`, the frame's sums' own.
constexpr double kKernelLatticeMargin = 4;
double kernel_lattice_pitch(const KernelSummationSpec& spec, double frame_pitch);

// The last kernel summation made (its kernels and their spectra), kept for the next call of the
// same job that asks for the same one: a wavelength's positive and negative power are two calls
// (spectral_diffraction.cpp), and its kernels are the same for both. A job's settings are
// fixed; what may change between calls is the camera, the wavelength, the depth range and the
// lattice, and they are the key.
class KernelSummationMemo {
public:
    using Make = std::function<Result<KernelSummation>()>;
    // The kept one where `spec` and `pitch` match it, else `make`'s (then kept instead).
    Result<std::shared_ptr<const KernelSummation>> get(const KernelSummationSpec& spec, double pitch, const Make& make);

private:
    std::mutex busy_;
    KernelSummationSpec spec_;
    double pitch_ = 0;
    std::shared_ptr<const KernelSummation> kept_;
};

// diffract_monochrome (scene_diffraction.h) with the job's memo: one job's calls, one at a time.
Result<bool> diffract_monochrome(const MonochromeScene& scene, double wavelength, const SceneSumSettings& s,
                                 const ComputeDevice& device, float* irradiance, const ProgressFn& progress,
                                 SumReport* report, KernelSummationMemo* memo);

}  // namespace wavecam::detail
