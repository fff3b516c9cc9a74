// The fast path: the same physics as the exact method (every pixel a source whose image is
// the wave PSF for its depth, field position and wavelength), evaluated as a spatially
// varying convolution instead of a sum over pinhole samples.
//
// PSFs come from fresnel_psf.h on a grid of depth layers (even in 1/z, spaced so the defocus
// phase over the pinhole changes by at most 0.3 rad between layers) x field anchors x
// wavelengths, and are folded over wavelength into nine RGB -> XYZ kernels per grid point
// (the basis is linear). The image is cut into tiles; the sources of one tile and one layer
// are convolved, by FFT, with the kernel interpolated (bilinearly over the anchors) at the
// tile centre, and the results overlap-add: each source is spread by (nearly) its own PSF.
// A source's light is shared linearly (in 1/z) between the two layers around its depth.
//
// Approximations, and where they break: a source takes the PSF of its tile centre and a blend
// of its two layers' (errors grow with tile size on very wide fields and with layer spacing); the
// kernel is cut at max_radius pixels (the energy beyond is renormalised into the kernel:
// large geometric blurs - pinholes many times the optimum - lose their tails). Layers are
// added, not composited: the render already holds only what the pinhole's centre sees, and
// the parallax across a pinhole (d / z, about a milliradian) is below a pixel, so a nearer
// layer hides nothing more; depth-of-field tools composite because a lens aperture is
// centimetres wide. This matches the exact method, which also sums every visible pixel.
#pragma once
#include "wavecam/spectral_diffraction.h"

namespace wavecam {

struct FastSettings {
    int tile = 128;        // tile side in pixels
    int max_radius = 32;   // kernel half-width cap (65 x 65 kernels)
    int anchors_x = 0;     // field anchors across; 0 = from the image's aspect (about 5 x 3)
    int anchors_y = 0;
    int nthreads = 0;
};

// Writes XYZ of the film image, exposed and vignetted exactly as diffract_spectral does.
Result<bool> diffract_fast(const SpectralScene& scene, const SpectralBasis& basis, const Aperture& aperture,
                           bool vignetting, float* xyz, const FastSettings& settings = {},
                           const ProgressFn& progress = {});

}  // namespace wavecam
