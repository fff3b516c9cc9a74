// The convolution method: the same physics as the scene-sum methods (every pixel a source whose
// image is the wave PSF for its depth, field position and wavelength), evaluated as a spatially
// varying convolution instead of a sum over pinhole samples.
//
// A ConvolutionPlan holds everything that depends only on the camera, the pinhole, the wavelengths,
// the colour basis and the depth range: the kernel table (kernel_table.h: depth layers even in 1/z x
// field anchors, the wavelength sum folded into nine RGB -> XYZ kernels per grid point) and
// the kernels' spectra for the tiled FFT convolution (anchored_convolution.h). It is built
// once (create) and applied to any number of frames that share those (apply), as Embree's
// scenes are created, committed, then used.
//
// Each source is spread by the PSF interpolated at its own position: bilinearly over the
// field anchors and linearly in 1/z between its two depth layers, so a source's light never
// changes when it crosses a tile boundary (no seams). Kernels hold a stated fraction of the
// PSF's energy (fresnel_psf.h, psf_kernel_radius); what lies beyond is spread as the far tail.
// For a pinhole in the Fraunhofer regime (a PSF no source depth changes) the PSF is one function
// of the difference of direction cosines at every field, and the plan convolves there instead:
// once for the whole frame, no anchors (in_directions).
//
// The frame's edge. Film pixels near the border receive light from scene points outside the
// frame. The plan's source domain is the output frame widened by the kernel radius on every
// side: those sources come from the input's overscan margin where it has one, and beyond it
// from the scene continued as its edge (each missing pixel takes the nearest edge pixel's
// radiance and depth, at its own field position). A uniform wall then comes back uniform to
// the last pixel.
//
// Layers are added, not composited: the render already holds only what the pinhole's centre
// sees, and the parallax across a pinhole (d / z, about a milliradian) is below a pixel, so a
// nearer layer hides nothing more; depth-of-field tools composite because a lens aperture is
// centimetres wide. This matches the scene-sum methods, which also sum every visible pixel.
#pragma once
#include <memory>
#include "wavecam/aperture.h"
#include "wavecam/progress.h"
#include "wavecam/spectral_scene.h"
#include "wavecam/spectrum.h"

namespace wavecam {

struct ConvolutionSettings {
    int tile = 0;            // tile side in pixels (at least the kernel radius); 0 = the cheapest tiling
    int max_radius = 512;    // safety bound on the kernel half-width (pixels)
    int anchor_cells = 4;    // field-anchor cells across the frame's long side
    int nthreads = 0;
    // Where kernels wide against the frame make one whole-domain tile and a set of its working
    // arrays per thread would pass this many bytes, the threads share one set, each step spread
    // over them (slower, a set's memory instead of one a thread).
    double tile_memory = 1024.0 * (1 << 20);
};

// What a plan is built for.
struct ConvolutionPlanSpec {
    PinholeCamera camera;            // the input render as it was made (overscan included)
    int overscan = 0;                // pixels of margin on every side: sources, not output
    Aperture aperture;
    SpectralBasis basis;
    double max_inverse_depth = 0;    // 1/z (planar) of the nearest source served (0: all sky)
    ConvolutionSettings settings;
};

class ConvolutionPlan {
public:
    // Builds the kernel table and kernel spectra (the costly part: progress reports it).
    static Result<std::shared_ptr<const ConvolutionPlan>> create(const ConvolutionPlanSpec& spec, const ProgressFn& progress = {});

    // Whether this plan serves a frame of `spec` (same geometry, pinhole, colour and settings,
    // and no source nearer than the plan's layers reach).
    bool serves(const ConvolutionPlanSpec& spec) const;

    // Writes XYZ of the output frame ((width - 2 overscan) x (height - 2 overscan)), exposed
    // and vignetted as diffract_spectral does. `scene.camera` must be the plan's camera.
    Result<bool> apply(const SpectralScene& scene, bool vignetting, float* xyz, const ProgressFn& progress = {}) const;

    int kernel_radius() const;
    // Whether the plan convolves in direction cosines: one shift-invariant convolution, for a
    // pinhole in the Fraunhofer regime whose PSF core spans several pixels, where that costs less
    // than the field anchors (the same PSFs; core/src/convolution/direction_convolution.h).
    bool in_directions() const;
    // The kernel radius (pixels) a plan for `spec` takes, without building it; 0 when none can be made.
    static int kernel_radius(const ConvolutionPlanSpec& spec);
    // Bytes a plan for `spec` and one frame's work need at their peak, without building it.
    static double estimate_bytes(const ConvolutionPlanSpec& spec);

    ~ConvolutionPlan();
    struct Impl;

private:
    explicit ConvolutionPlan(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// One frame, one plan: check its pixels (unless scene.checked), create, apply (tests and one-off calls).
Result<bool> diffract_convolution(const SpectralScene& scene, const SpectralBasis& basis, const Aperture& aperture,
                                  const XyzOutput& out, const ConvolutionSettings& settings = {},
                                  const ProgressFn& progress = {});

}  // namespace wavecam
