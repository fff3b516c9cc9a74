// The convolution method's kernel table: point-source images on a grid of depth layers x field anchors,
// each folded over wavelength into nine RGB -> XYZ kernels (the spectral basis is linear, so
// the wavelength sum need not be carried through the convolution). Internal to core.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>
#include "base/large_array.h"
#include "wavecam/pinhole_camera.h"
#include "wavecam/progress.h"
#include "wavecam/result.h"
#include "wavecam/spectrum.h"
#include "wavecam/aperture.h"
#include "wavecam/fresnel_psf.h"

namespace wavecam::detail {

// Depth layers spaced evenly in inverse depth w = 1/z from 0 (sky) to the nearest source:
// the pupil's quadratic phase goes as (1/z + 1/f) a^2 pi / lambda, so even steps in w are even
// steps of defocus phase. Steps of at most 0.3 rad at the shortest wavelength keep linear
// interpolation between neighbouring layers' PSFs within the convolution method's 2%. Large pinholes are
// in the geometric regime, where the PSF is the blur disc of radius a (1 + f w), itself linear
// in w: there steps that change the disc by at most half a pixel suffice (the larger step of
// the two is taken; at most 16 layers). Where the defocus phase stays within 0.3 rad even at
// the nearest source (small pinholes), one layer serves every depth (kernel_table.cpp says why).
struct DepthLayers {
    int count = 1;
    double step = 1.0;  // in 1/m

    static DepthLayers spanning(double max_inverse_depth, double aperture_radius, double shortest_wavelength,
                                double film_distance, double pixel_pitch);
    // The defocus phase at the pupil's rim for a source at inverse depth w: pi a^2 (w + 1/f) / lambda.
    static double rim_phase(double w, double aperture_radius, double wavelength, double film_distance) {
        return M_PI * aperture_radius * aperture_radius * (w + 1.0 / film_distance) / wavelength;
    }
    double inverse_depth(int layer) const { return layer * step; }
    // The layer at or below inverse depth w and the share of w's light that goes to the layer
    // above (linear in w).
    void locate(double w, int& lower, float& upper_share) const;
};

// Knots of the field-anchor grid along one axis of the source domain, in pixels. The outermost
// two lie `inset` pixels inside the domain's ends, on the output frame's edges, and sources
// beyond them (the margin, at most a kernel radius outside the frame) take the edge anchors'
// kernels. Knots on the domain's ends instead would put the anchors of a frame not much wider
// than 2 R at field angles far beyond the frame's, and the PSF changes with the field angle
// (1/cos^3 radially): an 18 px frame at f = 2 mm with R = 26 blended four PSFs 20deg off axis,
// 21% wider, for every source, 3% RMS off the exact sum.
// The convolution method's knots are evenly spaced and mirror-symmetric about the frame's
// centre (the optical axis), so that an aperture even in x or y gives mirror pairs of anchors
// whose PSFs are each other's mirror images: one is computed, the other flipped.
// Cells are at least kMinCellRadii kernel radii wide: the bilinear weights bend at the knots,
// and a uniform scene then shows a ripple there of about (R / cell)^2 times the difference of
// neighbouring kernels' widths (0.4% at cells of 3 R, 0.07% at 6 R, measured on a wall at
// 40deg); the field varies slowly, so wide cells lose nothing.
constexpr int kMinCellRadii = 6;
// Anchors must also follow the field. Off axis the PSF is stretched by 1/cos^3 of the field
// angle radially and 1/cos tangentially (Fraunhofer optics on a flat film: the aperture
// foreshortened by cos, the path f / cos, the film oblique to the ray), so a blend of the
// anchors' PSFs has the width their stretches' blend gives. The log of the area's stretch,
// m = 2 ln(1 + t^2) at t = tan(angle) (t^2 = u^2 + v^2 in the tangent plane), has Laplacian
// 8 / (1 + t^2)^2, at most 8, on the axis; bilinear interpolation over a cell of side h
// (tangent units) errs by at most h^2 / 8 times it, h^2, and a PSF's peak goes as its area's
// inverse. Cells at most kMaxAnchorStep = 0.1 wide keep the blend's peak within 1% of the
// PSF's at its own field, at any field. Where the ripple rule's cells are wider they are
// split evenly. Without the split a frame of a few hundred pixels had one cell whose knots
// were the frame's corners, and every source took the corners' PSFs, 1/cos^3 too wide: 63%
// below its Airy peak at the centre of a 60 deg frame.
constexpr double kMaxAnchorStep = 0.1;
// The stretch is diffraction's: the geometric shadow of a pinhole on a film parallel to it keeps
// its size at every field. A PSF whose width is shared between diffraction (the Airy radius
// 1.22 lambda f / D) and the shadow (radius D / 2) stretches by diffraction's share s of its
// variance, and a PSF narrower than a pixel changes a pixel's value little whatever its width
// (the pixel's own variance, 1/12 of its width squared per axis, takes a share p' of the sum):
// cells may then be kMaxAnchorStep / sqrt(s (1 - p')) wide for the same 1% at the peak, at
// most twice kMaxAnchorStep (a shadow's Fresnel rim still changes with the field). For
// the longest wavelength and the sky (the most diffraction's case), `pixel_pitch` on the film.
double anchor_step(const Aperture& aperture, double longest_wavelength, double film_distance, double pixel_pitch);
struct AnchorAxis {
    std::vector<int> knots;

    // `cells` equal cells (to the pixel) over [inset, inset + span], mirror-symmetric about its
    // middle (one more where the span is odd and `cells` even: no knot can lie on a half pixel).
    static AnchorAxis even(int inset, int span, int cells);
    // How many cells a span of `span` pixels takes: the ripple rule's (at most `ripple`, each at
    // least `min_cell` pixels wide), or more where the field's stretch asks for them (cells at
    // most `max_step` wide in the tangent plane, where a pixel is `tan_pitch` wide).
    static int cell_count(int span, int ripple, int min_cell, double tan_pitch, double max_step);
    int cells() const { return int(knots.size()) - 1; }
    int cell_of(int pixel) const;
    // The bilinear hat of knot k at pixel `pixel` (its centre): 1 on the knot, 0 at the
    // neighbouring knots and beyond; the outermost knots keep 1 beyond them.
    double hat(int k, int pixel) const {
        const int cell = cell_of(pixel);
        const double t = upper_weight(cell, pixel);
        return k == cell ? 1 - t : k == cell + 1 ? t : 0.0;
    }
    // Weight of the cell's upper knot for pixel `pixel` (its centre), 0..1 (0 or 1 beyond the
    // outermost knots).
    double upper_weight(int cell, int pixel) const {
        return std::clamp((pixel + 0.5 - knots[cell]) / double(knots[cell + 1] - knots[cell]), 0.0, 1.0);
    }
};

// The geometry the table is built for: the source domain's pixel (0, 0) is the camera's pixel
// (origin, origin); the domain may reach beyond the camera's frame on every side.
struct KernelTableSpec {
    PinholeCamera camera;
    int origin = 0;
    int domain_width = 0, domain_height = 0;
    int tile = 0, anchor_cells = 4, radius = 0;
    bool tiles_on_cells = false;  // the convolution's tiles split the anchor cells (tile_edges)
    Aperture aperture;
    const SpectralBasis* basis = nullptr;
    DepthLayers layers;
    int nthreads = 1;
};

// The computed anchors' kernels: (2 radius + 1)^2 weights each, m = 3 p + q (primary p -> XYZ
// q); a mirror image's are its source's read mirrored (never stored: at a small pinhole's
// 470 px kernels the copies were 440 MB of a 512x512 frame's 640).
struct KernelTable {
    int radius = 0;
    DepthLayers layers;
    AnchorAxis ax, ay;
    LargeArray<float> weights;
    std::vector<float> deficit;  // (layer, anchor, m): the share of the PSFs' power beyond the kernel
    // per anchor: the anchor whose kernels, mirrored across the axis where its knot differs, are
    // this one's (itself where its own were computed)
    std::vector<int> source;
    // per anchor: its place among the computed anchors (-1 for a mirror image), and how many
    std::vector<int> slot;
    int computed = 0;
    // whether anchor a's kernels are its source's with the columns (x) or rows (y) reversed
    bool mirrored_x(int a) const { return source[a] % ax.knots.size() != a % ax.knots.size(); }
    bool mirrored_y(int a) const { return source[a] / ax.knots.size() != a / ax.knots.size(); }

    int anchors() const { return int(ax.knots.size() * ay.knots.size()); }
    size_t kernel_size() const { return size_t(2 * radius + 1) * (2 * radius + 1); }
    // kernel k = (layer x computed + slot) x 9 + m
    const float* kernel(long k) const { return &weights[size_t(k) * kernel_size()]; }
    long kernel_index(int layer, int anchor, int m) const { return (long(layer) * computed + slot[anchor]) * 9 + m; }
};

// The anchor axis build_kernel_table lays out across (vertical: down) the spec's domain:
// anchor_cells cells across, fewer down in proportion when the domain is wider than tall, each
// at least kMinCellRadii kernel radii wide; more where the field's stretch asks for them
// (anchor_step).
AnchorAxis anchor_axis(const KernelTableSpec& spec, bool vertical);

// Per anchor of the grid ax x ay: the anchor whose kernels, mirrored across the optical axis, are
// its own (the lower index of each mirror pair; itself where it has no mirror image). The axis
// lies at half of `axis2x` (`axis2y`) in the knots' coordinates; an axis is mirrored only where
// the aperture is even along it and its knots are symmetric about the optical axis.
std::vector<int> mirror_sources(const AnchorAxis& ax, const AnchorAxis& ay, int axis2x, int axis2y, bool even_x,
                                bool even_y);
// The convolution method's (KernelTable::source).
std::vector<int> anchor_sources(const KernelTableSpec& spec, const AnchorAxis& ax, const AnchorAxis& ay);
// How many anchors of that grid are their own source: those whose kernels are computed.
int computed_anchors(const KernelTableSpec& spec, const AnchorAxis& ax, const AnchorAxis& ay);

// Adds wavelength s's PSF (field_psf_kernel's: shares of the power through the pinhole) to the
// nine kernels m = 3 p + q of side 2 radius + 1 (the PSF centred in them), each weighted by the
// basis's power of primary p times XYZ q per unit power at s, and what the PSF does not hold to
// their deficits.
void add_wavelength(const PsfKernel& psf, const SpectralBasis& basis, int s, int radius, float* const kernels[9],
                    float* deficit);

// Fails only when cancelled through `progress`.
Result<KernelTable> build_kernel_table(const KernelTableSpec& spec, const ProgressFn& progress);

}  // namespace wavecam::detail
