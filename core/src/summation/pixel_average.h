// How well n x n film points average a pixel (the scene-sum methods' film sampling, scene_diffraction.h).
//
// A pixel of width p records the irradiance averaged over its area: at spatial frequency f the
// box filter sinc(f p). n points at the centres of an n-split of the pixel give instead the
// midpoint rule's D_n(x) = sin(pi x) / (n sin(pi x / n)), x = f p (its first alias, D_n = +-1,
// at x = n). The irradiance of an incoherent image through a pupil of width D holds frequencies
// up to fc = D / (lambda f), weighted by the optical transfer function, for a circular pupil
// OTF(nu) = (2 / pi)(acos nu - nu sqrt(1 - nu^2)), nu = f / fc (Goodman, Introduction to Fourier
// Optics, 3rd ed., eq. 6-32). The error of a pixel's value at one frequency is then at most
// |sinc(x) - D_n(x)| OTF(x / (p fc)) of that frequency's amplitude. Internal to core.
#pragma once

namespace wavecam::detail {

// max over 0 < x <= p fc of |sinc(x) - D_n(x)| OTF(x / (p fc)).
double pixel_average_error(int n, double pixel_times_cutoff);

}  // namespace wavecam::detail
