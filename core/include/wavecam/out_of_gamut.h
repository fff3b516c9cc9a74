// Colours outside the output space's gamut. The film's CIE XYZ is never negative (every
// non-negative spectrum lies inside the spectral locus), but a narrow working space such as
// linear Rec.709 cannot hold every real colour: spectrally pure light in a diffraction fringe,
// or one random-phase run's speckle lit by a narrow band of wavelengths, has a negative
// component there. This pulls such a colour toward the grey of the same luminance just far
// enough that its lowest component is zero (docs/colour.md says why this and not another way).
#pragma once
#include <cstddef>
#include "wavecam/matrix3.h"

namespace wavecam {

// Maps each of `count` linear RGB triplets with a negative component into the gamut, in place:
//   Y  = yR r + yG g + yB b                  (luminance; y = `primary_luminance`, the Y of each
//                                             unit primary: row Y of the space's RGB -> XYZ)
//   w  = Y / (yR + yG + yB)                  (the grey (w, w, w) of the same luminance)
//   c' = w + t (c - w),  t = w / (w - min c) (the largest t in [0, 1] with no component < 0)
// Y is kept exactly (c' - w is a multiple of c - w, whose luminance is 0), as is the hue line
// through the space's white; colours with no negative component are not touched, so the
// in-gamut round trip RGB -> spectrum -> XYZ -> RGB is unaffected. A colour with Y <= 0 (no
// light; only rounding makes one) becomes black. Returns how many triplets were changed.
size_t desaturate_into_gamut(float* rgb, size_t count, const Vector3& primary_luminance);

}  // namespace wavecam
