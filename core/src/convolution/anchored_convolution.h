// A spatially varying convolution that is continuous over the field: each source is spread by
// the kernel interpolated at its own position (bilinearly over the kernel table's anchors,
// linearly in 1/z over its two depth layers). Internal to core.
//
// Why interpolate per source. Cutting the image into tiles that each take one kernel makes a
// source's image jump when it crosses a tile boundary: a grid of seams. Here the weight of a
// source for anchor a is the bilinear hat function phi_a at its position (the hats sum to 1),
// the weighted image phi_a s is convolved with anchor a's kernel, and the results add:
//   out = sum_a K_a * (phi_a s),   so source s is spread by sum_a phi_a(s) K_a,
// which varies smoothly with the source's position, keeps its energy and centroid, and does
// not depend on the tiling (tiles only bound the FFT size; overlap-add makes them exact).
// A tile meets the anchors of every cell it spans (four where it lies within one cell).
// Interpolating the kernel at the output pixel instead (out = sum_a phi_a (K_a * s)) would
// cost fewer transforms but spreads one source's light by a blend that changes across its
// own image; the per-source form is the physical one (each source has one PSF).
#pragma once
#include <complex>
#include <cstdint>
#include <vector>
#include "base/large_array.h"
#include "wavecam/edge_continuation.h"
#include "convolution/kernel_table.h"
#include "convolution/output_window.h"

namespace wavecam::detail {

// The sources on the convolution's domain: each pixel's depth layers, and its light read from
// the frame as a tile needs it (a copy of the domain's radiance was the largest array after
// the kernel spectra): the frame's own, its edge continued beyond (edge_continuation.h), times
// the source's natural cos^4 fall-off at its own field position, cos^2 = 1 / (1 + u^2 + v^2)
// with u, v the pixel centre's tangents (pinhole_camera.h).
struct DomainSources {
    int width = 0, height = 0;
    const EdgeContinuation* frame = nullptr;  // the frame's light, 3 per pixel
    int origin = 0;                           // domain pixel (i, j) is the frame's (i - origin, j - origin)
    std::vector<double> u, v;                 // per domain column, per domain row: the tangents
    std::vector<uint8_t> lower;               // layer at or below the pixel's 1/z
    std::vector<float> upper_share;           // share of its light in the layer above

    float light(int i, int j, int p) const {
        const double c2 = 1.0 / (1.0 + u[i] * u[i] + v[j] * v[j]);
        return float(frame->light(i - origin, j - origin)[p] * c2 * c2);
    }
};

// FFT length along one axis of a domain `length` long, for tiles of side `tile` and kernels of
// radius R. Overlap-add needs tile + 2R: a tile's light reaches R beyond it. Where one tile
// covers the axis it needs only the domain's length: the domain is the output widened by R on
// every side, so what wraps round the period (at most R beyond the domain) lands in that margin,
// which is never read. Each axis on its own: a strip's short side is one tile of its own length.
int convolution_fft_length(int tile, int radius, int length);

// The anchor cells' edges along one axis of a domain `length` long, the margins joined to the
// edge cells: the knots, the outermost moved to the domain's ends.
std::vector<int> cell_edges(const AnchorAxis& knots, int length);

// The tiles' edges along one axis of a domain `length` long, tiles at most `tile` wide, kernels
// of radius R: even tiles from the domain's start, or (`on_cells`) tiles of whole anchor cells
// (as many as fit in `tile`; a wider cell split into equal tiles), so that a tile meets only
// the knots of the cells it holds instead of the extra one of a cell it straddles. Even tiles
// where that would give a tile narrower than R.
std::vector<int> tile_edges(const AnchorAxis& knots, int length, int tile, int radius, bool on_cells);

// Every how many tiles along an axis with tile edges `edges` one overlap-add pass takes a tile:
// the least P >= 2 for which the P - 1 tiles between two of a pass span 2 R, so that what they
// write R beyond themselves never meets (2 for tiles of 2 R or more, 3 for tiles of R or more).
int pass_period(const std::vector<int>& edges, int radius);

// Kernel spectra a plan keeps at most; beyond, each tile transforms the kernels it meets (a
// frame with hundreds of anchors at a wide field: 4x the transforms, memory bounded).
constexpr double kMaxKernelSpectraBytes = 1024.0 * (1 << 20);

// Whether a plan keeps its `count` kernel spectra of `size` values for `tiles` tiles: where they
// fit, and where tiles share them (one tile transforms each group's kernels once, as a plan
// would, and keeps none: a small pinhole's whole-domain tile held a GiB of them).
inline bool keeps_kernel_spectra(double count, double size, double tiles) {
    return tiles > 1 && count * size * 8 <= kMaxKernelSpectraBytes;
}

// The bytes of one set of a tile's working arrays: its transform's image (`points`) and the
// tile's weights, the transform's three arrays, the three accumulated spectra, and the input
// spectra: one and the tile's light, or, where no kernel spectra are kept, one per anchor of a
// group (`inputs`) and one kernel's.
inline double tile_scratch_bytes(double points, double tile_pixels, double spectrum_size, int inputs, bool own_kernels) {
    return (points + tile_pixels * (own_kernels ? 1 : 4)) * 4 + (6 + inputs + (own_kernels ? 1 : 0)) * spectrum_size * 8;
}

// Whether the threads share one set of arrays, each step spread over them, for a plan of fewer
// tiles than threads: where a set each would pass `limit` bytes (ConvolutionSettings::tile_memory;
// a 4K frame's tile at a small pinhole held 1.6 GB of them). A set each is faster where they
// fit: each thread takes whole kernel groups, no step waits for another.
inline bool shares_tile_scratch(double tiles, int threads, double set_bytes, double limit) {
    return tiles < threads && threads * set_bytes > limit;
}

class RealFft2D;

// A kernel of (2 R + 1)^2 weights centred on the origin of an Nx x Ny transform (wrapped), into
// `spectrum`; `image` is the transform's Nx x Ny of zeros and is left so. Its loops spread over
// `threads`.
void transform_centred_kernel(const float* kernel, int R, RealFft2D& fft, int Nx, int Ny, float* image,
                              std::complex<float>* spectrum, int threads);

// A tile's source pixels [x0, x1) x [y0, y1) of the domain.
struct TileBounds {
    int x0, y0, x1, y1;
};

class AnchoredConvolution {
public:
    // Transforms every kernel of `table` once, for tiles of side `tile` (>= the radius) on a
    // source domain of width x height.
    // `tile_memory`: ConvolutionSettings::tile_memory.
    static Result<AnchoredConvolution> create(KernelTable table, int tile, bool tiles_on_cells, int width, int height,
                                              int nthreads, double tile_memory, const ProgressFn& progress);

    // Adds to `xyz` (interleaved, out.width x out.height) the image of `sources` on the output
    // window `out`.
    Result<bool> apply(const DomainSources& sources, const OutputWindow& out, float* xyz,
                       const ProgressFn& progress) const;

    // A kernel's spectrum as kept: the rows read as N - r (flip_rows) and conjugated for a
    // kernel that is its source's mirror image (kernel_table.h).
    struct KernelView {
        const std::complex<float>* data;
        bool flip_rows, conjugate;
    };

    const KernelTable& table() const { return table_; }
    int tile() const { return tile_; }
    bool tiles_on_cells() const { return tiles_on_cells_; }

private:
    KernelTable table_;
    int tile_ = 0, fft_width_ = 0, fft_height_ = 0, nthreads_ = 1;
    double tile_memory_ = 0;
    bool tiles_on_cells_ = false;
    std::vector<int> edges_x_, edges_y_;  // tile_edges across and down the domain
    size_t spectrum_size_ = 0;
    LargeArray<std::complex<float>> kernel_spectra_;  // [layer][slot][m][spectrum]; empty: none kept
    // kernel k (KernelTable::kernel_index)'s spectrum into `spectrum` (`image`: the
    // transform's height x width of zeros, left so), its loops spread over `threads`
    void transform_kernel(long k, RealFft2D& fft, float* image, std::complex<float>* spectrum, int threads) const;
    KernelView spectrum(int layer, int anchor, int m) const;

    struct TileScratch;
    struct KernelGroup;
    std::vector<KernelGroup> groups_of(const DomainSources& src, const TileBounds& b) const;
    // adds the group's anchors' light (each anchor's share of the tile's sources, convolved
    // with its kernels) to s.acc
    void add_group(const DomainSources& src, const TileBounds& b, const KernelGroup& g, TileScratch& s) const;
    // the anchor's light of primary p (its weights in s.weight, lighting the tile's columns
    // [first, last)) into s.image, the tile's corner at its origin, transformed into `in`
    void light_spectrum(const DomainSources& src, const TileBounds& b, int first, int last, int p, TileScratch& s,
                        std::complex<float>* in) const;
    // channel q of acc, transformed back, added to the output window
    void add_tile_light(const TileBounds& b, std::complex<float>* acc, int q, const OutputWindow& out, float* xyz,
                        TileScratch& s) const;
};

}  // namespace wavecam::detail
