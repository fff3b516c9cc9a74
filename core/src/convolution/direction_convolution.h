// The convolution in direction cosines, for pinholes in the Fraunhofer regime. Internal to core.
//
// A planar pupil sends a plane wave from the direction n_in to the directions n with power
// |P^((n - n_in)_transverse / lambda)|^2 per unit of direction cosines (direction_cosines.h): one
// function of the difference of directions for every source at every field. The stretch of the
// field anchors' PSFs on a flat film (1/cos^3 radially, 1/cos tangentially, kernel_table.h) is
// that function seen through the film's mapping to directions. Where the pupil's defocus phase pi
// a^2 (1/z + 1/f) / lambda stays within kMaxFraunhoferPhase for every source and wavelength, the
// whole frame is then one shift-invariant convolution in direction cosines:
//   1. each source's light (radiance x its cos^4, as the anchored convolution carries it) is
//      spread bilinearly over the four cells of a grid in direction cosines round its direction
//      (its power and centroid kept); beyond the domain's margin the frame's edge is continued
//      on the grid itself, over every direction of the disc that the kernels reach;
//   2. the grid is convolved with the nine on-axis kernels, computed on the grid's cells (one
//      transform per primary and three back, instead of three per anchor a tile meets);
//   3. each film pixel takes the convolved light at its own direction (bilinearly) over a cell's
//      area, times its own area in axis pixels, cos^4.
// Each source's light is weighted by cos(out) / cos(in): Rayleigh-Sommerfeld's obliquity and the
// film's incidence (spectral_diffraction.cpp takes |U|^2 cos(out)) against the pattern's power
// per unit of direction cosines; a film kernel holds its own field's value of it throughout.
// Cells are a fraction of the PSF's core: spreading and reading back each widen the image by
// about a cell's variance (h^2 / 6 per axis), so a core of standard deviation sigma loses a
// share h^2 / (3 sigma^2) of its peak; cells of at most sigma / kCoreCells keep that within 0.5%.
// A film pixel takes the light at its centre, not its area's mean: the image is then sharper by
// the pixel's variance (1/12 of its side squared per axis), a share 1 / (12 sigma^2) of the peak,
// within 0.5% for cores of kCorePixels axis pixels or more; narrower PSFs take the anchors.
// The pupil's field-dependent defocus (cos^3 alpha radially, cos alpha tangentially) is taken
// as the axis's: within kMaxFraunhoferPhase, by Marechal's rule at most phi^2 / 12 of the light
// moves (0.75%). What the kernels do not hold goes to the far tail (far_tail.h), as the anchored
// kernels' does.
#pragma once
#include <complex>
#include <vector>

#include "base/large_array.h"
#include "convolution/anchored_convolution.h"
#include "convolution/direction_cosines.h"
#include "convolution/kernel_table.h"
#include "convolution/output_window.h"
#include "wavecam/progress.h"

namespace wavecam::detail {

constexpr double kMaxFraunhoferPhase = 0.3;  // radians of defocus over the pupil, at the nearest source
constexpr double kCoreCells = 8.2;           // cells across a PSF core's standard deviation, at least
constexpr double kCorePixels = 4;            // axis pixels across it, at least

// The cell (axis pixels) of the direction grid for `spec`'s pinhole, or 0 where the pinhole is not
// in the Fraunhofer regime for its nearest source and shortest wavelength, or its core spans
// fewer than kCorePixels.
double fraunhofer_cell(const KernelTableSpec& spec, double max_inverse_depth);

// The grid of cells in direction cosines (axis pixels; the row axis downward, as the film's) that
// holds every source whose kernel reaches the output frame: cell (I, J) is centred on (a0 + I
// cell, b0 + J cell).
struct DirectionGrid {
    double cell = 1, a0 = 0, b0 = 0;
    int width = 0, height = 0;     // the cells that hold sources
    int fft_width = 0, fft_height = 0;
    int radius = 0;                // the kernels' half-width, in cells

    // The output frame's directions widened by the kernels' reach, within the disc of
    // directions; kernels that hold kPsfKernelEnergy of the on-axis PSF, at most the plan's
    // radius; a transform period that wraps nothing onto the output's cells.
    static DirectionGrid covering(const KernelTableSpec& spec, double cell);
    // the grid position of tangent (u, v), in cells
    void position(const DirectionCosines& dc, double u, double v, double& x, double& y) const;
};

class DirectionConvolution {
public:
    // The nine on-axis kernels on the grid's cells, transformed; the far tail's table (one cell
    // of anchors and one layer: the same deficits everywhere).
    static Result<DirectionConvolution> create(const KernelTableSpec& spec, double cell, const ProgressFn& progress);

    // Adds to `xyz` (interleaved, out.width x out.height) the image of `sources` on the output
    // window `out` (only their light is read: one layer serves every depth).
    Result<bool> apply(const DomainSources& sources, const OutputWindow& out, float* xyz,
                       const ProgressFn& progress) const;

    // The deficits the far tail spreads, and where the kernels end (axis pixels).
    const KernelTable& tail_table() const { return tail_; }
    double kernel_edge() const { return grid_.radius * grid_.cell; }
    const DirectionGrid& grid() const { return grid_; }

    // The bytes create and apply need at their peak, for `spec` and `cell`.
    static double estimate_bytes(const KernelTableSpec& spec, double cell);

private:
    DirectionGrid grid_;
    PinholeCamera camera_;
    int nthreads_ = 1;
    size_t spectrum_size_ = 0;
    LargeArray<std::complex<float>> kernel_spectra_;  // [m][spectrum]
    KernelTable tail_;
};

}  // namespace wavecam::detail
