// Procedural textures on a surface's (u, v) coordinates. Each returns how much ink covers
// the point, 0 (albedo) to 1 (ink colour); antialiasing comes from the pixel samples.
#pragma once
#include <string>
#include "vec3.h"

namespace wavecam::trace {

enum class TextureKind { None, Checker, Bars, SiemensStar, Text };

struct Texture {
    TextureKind kind = TextureKind::None;
    Vec3 ink{0.05, 0.05, 0.05};
    // Checker: squares per unit of (u, v). Bars: elements across u. Star: spoke pairs.
    int count = 8;
    std::string text;  // Text only: characters of the built-in 5x7 font
};

// Ink coverage at (u, v): 0 or 1.
//  checker: alternating squares, `count` per unit of u and v (repeats).
//  bars: line-pair resolution target in [0,1]^2; `count` square elements side by side along
//        u (make the surface count times wider than tall), element k with 3 bars of period
//        0.16 * 2^(-k/2) element widths: vertical bars in the upper half, horizontal in the lower.
//  star: Siemens star of `count` dark spokes filling the disc of diameter 1 centred at (0.5, 0.5).
//  text: the string in 5x7 glyphs on 6x9 cells filling [0,1]^2 (make the surface
//        6 n : 9 for n characters so the glyphs are not stretched).
double ink_coverage(const Texture& texture, double u, double v);

// Albedo with the texture applied: albedo (1 - c) + ink c.
Vec3 textured_albedo(Vec3 albedo, const Texture& texture, double u, double v);

}  // namespace wavecam::trace
