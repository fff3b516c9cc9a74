#include "summation/kernel/kernel_summation_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fft/column_fft.h"  // fft_friendly_size
#include "wavecam/fresnel_psf.h"
#include "wavecam/convolution_method.h"

namespace wavecam::detail {

DepthLayers amplitude_layers(double max_inverse_depth, double aperture_radius, double wavelength) {
    DepthLayers d;
    if (!(max_inverse_depth > 0)) return d;
    d.step = kMaxLayerPhase * wavelength / (M_PI * aperture_radius * aperture_radius);
    const double steps = std::ceil(max_inverse_depth / d.step);  // (a double: no overflow)
    d.count = int(std::min(steps, double(kMaxKernelLayers))) + 1;
    return d;
}

Result<bool> too_many_layers() {
    char m[200];
    std::snprintf(m, sizeof m,
                  "summation: kernel serves depths to %d layers at this pinhole and wavelength, this scene needs more "
                  "(its nearest source is too near for the pinhole's defocus); expected auto, direct or nufft",
                  kMaxKernelLayers);
    return Result<bool>::failure(m, ErrorKind::Invalid, "summation");
}

bool airy_spans_a_pixel(const KernelSummationSpec& s) {
    return 1.22 * s.wavelength * s.camera.film_distance / (2 * s.aperture.bounding_radius()) >= s.camera.pixel_pitch();
}

double kernel_energy(const KernelSummationSpec& s) {
    // (a PSF narrower than a pixel on the axis: the film pixels average its tail's cross terms,
    // and kernels holding more changed nothing there, kernel_summation.h)
    if (s.incoherent || !airy_spans_a_pixel(s)) return kPsfKernelEnergy;
    const double deficit = std::clamp(kFewRunsDeficit * s.runs / 64.0, kFewRunsDeficit, 1 - kPsfKernelEnergy);
    return 1 - deficit;
}

KernelSummationGeometry kernel_summation_geometry(const KernelSummationSpec& s) {
    const PinholeCamera& c = s.camera;
    const int o = s.overscan, out_w = c.width - 2 * o, out_h = c.height - 2 * o;
    const double nearest = s.max_inverse_depth > 0 ? 1.0 / s.max_inverse_depth : INFINITY;
    KernelSummationGeometry g;
    // the radius is the widest PSF's at the output frame's corners
    const WidestPsf widest{s.aperture, c.film_distance, nearest, s.wavelength,
                           c.cos_widest(o, o, o + out_w, o + out_h), kernel_energy(s)};
    g.radius = psf_kernel_radius(widest, c.pixel_pitch(), ConvolutionSettings{}.max_radius);
    g.origin = g.radius - o;
    g.width = out_w + 2 * g.radius;
    g.height = out_h + 2 * g.radius;
    // one transform over the whole domain: light wrapped round its period (at most R beyond the
    // domain) lands in the margin, which is never read
    g.nx = fft_friendly_size(g.width);
    g.ny = fft_friendly_size(g.height);
    const int longest = std::max(g.width, g.height), cells = std::max(1, s.anchor_cells);
    // cells as wide as the PSF allows (kMinAmplitudeCellRadii), the radius that holds
    // kPsfKernelEnergy: kernels that hold more for few runs must not spread the anchors
    WidestPsf core = widest;
    core.energy = kPsfKernelEnergy;
    const int min_cell =
        kMinAmplitudeCellRadii * psf_kernel_radius(core, c.pixel_pitch(), ConvolutionSettings{}.max_radius);
    // The anchors span the whole domain, the margin too: a margin source's PSF is its own
    // field's, stretched as 1/cos^3 radially (docs/physics.md, wide fields), wider than the frame
    // edge's. Taking the edge anchors' kernels for the margin made a 32 px frame at 60 deg (R =
    // 24: the margin reaches 55 deg and more, the frame's corner 39) differ from the point sums'
    // same runs by 2.2% RMS in its interior at 64 runs; anchors over the margin, 1.3%. Their
    // cells are as wide as that allows, and close enough that the field's stretch of the PSF
    // changes little between them (kernel_table.h). Even cells, mirror-symmetric about the
    // optical axis: a knot is a source pixel (its centre), so knots k and width - 1 - k are
    // mirror images, and where the aperture is even their kernels are each other's mirror images
    // (kernel_summation_kernels.cpp computes one of each pair).
    // The cells are 1/sqrt(2) of the convolution method's: its kernels blend powers, these
    // amplitudes, whose runs carry the cross terms of neighbouring anchors' kernels. Measured on
    // KernelSummation.UniformWallIsUniform (32 px, 50 deg): RMS 1.02% against the incoherent image at
    // cells of anchor_step, 0.69% at 0.8 or 0.7 of it.
    const double step = anchor_step(s.aperture, s.wavelength, c.film_distance, c.pixel_pitch()) / std::sqrt(2.0);
    auto axis = [&](int length) {
        const int span = length - 1, ripple = std::max(1, int(std::lround(double(cells) * length / longest)));
        int n = std::max(1, AnchorAxis::cell_count(span, ripple, min_cell, c.tan_pitch(), step));
        if (span % 2 == 0 && n % 2 == 1) ++n;  // (an odd frame: a knot on the axis pixel, the frame's centre)
        return AnchorAxis::even(0, span, n);
    };
    g.ax = axis(g.width);
    g.ay = axis(g.height);
    g.layers = amplitude_layers(s.max_inverse_depth, s.aperture.bounding_radius(), s.wavelength);
    return g;
}

int KernelSources::count() const {
    int n = 0;
    for (int a = 0; a < int(mirror.size()); ++a) n += summed(a);
    return n;
}

KernelSources kernel_sources(const KernelSummationSpec& s, const KernelSummationGeometry& g) {
    KernelSources k;
    k.mirror = mirror_sources(g.ax, g.ay, g.width - 1, g.height - 1, s.aperture.even_in_x(), s.aperture.even_in_y());
    k.transpose.assign(k.mirror.size(), -1);
    // (a square camera: its tangents' axes then meet the anchors' at the same knots)
    if (s.camera.width != s.camera.height || g.ax.knots != g.ay.knots || !s.aperture.even_across_antidiagonal())
        return k;
    const int n = int(g.ax.knots.size());
    for (int a = 0; a < int(k.mirror.size()); ++a) {
        const int t = (a % n) * n + a / n;
        if (t < a && k.mirror[size_t(a)] == a && k.mirror[size_t(t)] == t) k.transpose[size_t(a)] = t;
    }
    return k;
}

namespace {

// The widest turn, in direction sines along either axis, of any kernel's sum over the pinhole
// (kernel_lattice_pitch): from each anchor's source at the nearest layer to its kernel's film
// points' corners, the wavefronts' curvature at the rim added.
double widest_kernel_turn(const KernelSummationSpec& s, const KernelSummationGeometry& g) {
    const PinholeCamera& c = s.camera;
    const double a = s.aperture.bounding_radius(), w = g.layers.inverse_depth(std::max(0, g.layers.count - 1));
    double widest = 0;
    for (const int kx : g.ax.knots)
        for (const int ky : g.ay.knots) {
            const double px = kx - g.origin + 0.5, py = ky - g.origin + 0.5;
            double us, vs;
            c.tangent(px, py, us, vs);
            const double ns = std::sqrt(1 + us * us + vs * vs);
            for (const int dx : {-1, 1})
                for (const int dy : {-1, 1}) {
                    // the film point at the kernel's corner (its geometric image's direction, -d_t)
                    double ut, vt;
                    c.tangent(px + dx * (g.radius + 0.5), py + dy * (g.radius + 0.5), ut, vt);
                    const double nt = std::sqrt(1 + ut * ut + vt * vt);
                    const double turn = std::max(std::abs(us / ns - ut / nt), std::abs(vs / ns - vt / nt));
                    const double curvature = a * (w / ns + 1 / (c.film_distance * nt));
                    widest = std::max(widest, turn + curvature);
                }
        }
    return widest;
}

}  // namespace

double kernel_lattice_pitch(const KernelSummationSpec& spec, double frame_pitch) {
    const KernelSummationGeometry g = kernel_summation_geometry(spec);
    const double need = widest_kernel_turn(spec, g) + spec.wavelength / spec.aperture.diameter;
    const double pitch = std::min(spec.wavelength / (kKernelLatticeMargin * need),
                                  spec.aperture.diameter / kMinSamplesAcross);
    return std::max(frame_pitch, pitch);
}

}  // namespace wavecam::detail
