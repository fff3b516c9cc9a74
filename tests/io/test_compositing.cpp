// Alpha as coverage (docs/compositing.md): a premultiplied element diffracted alone and laid
// over a plate must give what diffracting the whole scene once gives. For a plate uniform at the
// element's depth, whole = D(e) + P D(1 - a) and over = D(e) + P (1 - a'), so the element's
// diffracted alpha a' must be D(a) / D(1), the coverage spread by the PSF that grey light takes.
// Checked at a narrow and a wide field, for a bright element on a dark plate and a dark one on a
// bright plate, against the whole scene through the same method; and the check fails when the
// alpha is passed through undiffracted.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>

#include <cmath>

#include "wavecam/diffract_image.h"

using namespace wavecam;

namespace {
constexpr int kW = 64;
constexpr float kDepth = 3.0f;

// Coverage of a disc of radius r about (cx, cy), its edge one pixel soft.
float disc(int i, int j, float cx, float cy, float r) {
    const float d = std::hypot(i + 0.5f - cx, j + 0.5f - cy);
    return std::clamp(r + 0.5f - d, 0.0f, 1.0f);
}

// RGBA + Z: the element (premultiplied `colour` x coverage) alone, or composited over `plate`
// (then opaque, no alpha channel).
OIIO::ImageBuf scene(double fov_deg, const float colour[3], float plate, bool whole) {
    OIIO::ImageSpec spec(kW, kW, whole ? 4 : 5, OIIO::TypeDesc::FLOAT);
    spec.channelnames = whole ? std::vector<std::string>{"R", "G", "B", "Z"}
                              : std::vector<std::string>{"R", "G", "B", "A", "Z"};
    if (!whole) spec.alpha_channel = 3;
    spec.attribute("wavecam.fov", float(fov_deg));
    OIIO::ImageBuf buf(spec);
    for (int j = 0; j < kW; ++j)
        for (int i = 0; i < kW; ++i) {
            // one disc at the centre, one towards the corner (the wide field's oblique PSFs)
            const float a = std::max(disc(i, j, 32, 32, 9), disc(i, j, 52, 50, 6));
            float px[5];
            for (int c = 0; c < 3; ++c) px[c] = colour[c] * a + (whole ? plate * (1 - a) : 0.0f);
            px[3] = whole ? kDepth : a;
            px[4] = kDepth;
            buf.setpixel(i, j, px);
        }
    return buf;
}

DiffractOptions options(double pinhole = 0.1e-3) {
    DiffractOptions o;
    o.film_distance = 10e-3;
    o.pinhole = pinhole;
    o.wavelength_count = 3;
    o.vignetting = false;  // the plate is laid over undiffracted: no fall-off on either side
    return o;
}

// Rec. 709 luminance weights (ITU-R BT.709): the grey that alpha's light is.
constexpr double kLuminance[3] = {0.2126, 0.7152, 0.0722};

struct Edge {
    double worst = 0;          // largest |over - whole| / plate in luminance, over the frame
    double worst_kept = 0;     // the same with the element's alpha passed through undiffracted
    double worst_channel = 0;  // largest |over - whole| / plate in any one channel
};

Edge compare_over(double fov_deg, double pinhole, const float colour[3], float plate) {
    OIIO::ImageBuf whole_out, element_out;
    EXPECT_TRUE(diffract(whole_out, scene(fov_deg, colour, plate, true), "whole", options(pinhole)))
        << whole_out.geterror();
    const OIIO::ImageBuf element = scene(fov_deg, colour, plate, false);
    EXPECT_TRUE(diffract(element_out, element, "element", options(pinhole))) << element_out.geterror();
    EXPECT_EQ(element_out.spec().alpha_channel, 3);
    Edge e;
    for (int j = 4; j < kW - 4; ++j)
        for (int i = 4; i < kW - 4; ++i) {
            const float a_in = element.getchannel(i, j, 0, 3), a_out = element_out.getchannel(i, j, 0, 3);
            double over = 0, kept = 0, whole = 0, worst_channel = 0;
            for (int c = 0; c < 3; ++c) {
                const double lit = element_out.getchannel(i, j, 0, c), w = whole_out.getchannel(i, j, 0, c);
                over += kLuminance[c] * (lit + plate * (1 - a_out));
                kept += kLuminance[c] * (lit + plate * (1 - a_in));
                whole += kLuminance[c] * w;
                worst_channel = std::max(worst_channel, std::fabs(lit + plate * (1 - a_out) - w));
            }
            e.worst = std::max(e.worst, std::fabs(over - whole) / plate);
            e.worst_kept = std::max(e.worst_kept, std::fabs(kept - whole) / plate);
            e.worst_channel = std::max(e.worst_channel, worst_channel / plate);
        }
    return e;
}
}  // namespace

// One alpha carries the coverage of grey light: in luminance the composite is the whole scene
// within 2% of the plate. Each colour's PSF is a little wider (red) or narrower (blue) than grey's,
// so one channel alone differs by that spread at an edge: within 2% near the optimum pinhole,
// several percent where diffraction dominates (docs/compositing.md has the figures).
TEST(Alpha, AnElementOverAPlateIsTheWholeSceneDiffractedOnce) {
    const float bright[3] = {2.0f, 1.5f, 1.0f}, dark[3] = {0.05f, 0.04f, 0.03f};
    struct Case {
        double pinhole, channel_bound;
    };
    // film 10 mm: 0.15 mm is about the optimum; 0.03 mm gives an Airy radius of 8 pixels at 10 deg
    for (const Case& k : {Case{0.15e-3, 0.02}, Case{0.03e-3, 0.12}})
        for (double fov : {10.0, 60.0}) {
            const Edge glow = compare_over(fov, k.pinhole, bright, 0.2f), fringe = compare_over(fov, k.pinhole, dark, 1.0f);
            EXPECT_LT(glow.worst, 0.02) << fov << " deg, bright element over a dark plate";
            EXPECT_LT(fringe.worst, 0.02) << fov << " deg, dark element over a bright plate";
            EXPECT_LT(std::max(glow.worst_channel, fringe.worst_channel), k.channel_bound) << fov;
            // the same comparison sees the fault it guards against: alpha left as it was
            EXPECT_GT(glow.worst_kept, 0.05) << fov;
            EXPECT_GT(fringe.worst_kept, 0.05) << fov;
            std::printf("%g mm, %g deg: over vs whole %.4f and %.4f of the plate in luminance, %.4f and %.4f in a "
                        "channel (undiffracted alpha: %.3f, %.3f)\n",
                        k.pinhole * 1e3, fov, glow.worst, fringe.worst, glow.worst_channel, fringe.worst_channel,
                        glow.worst_kept, fringe.worst_kept);
        }
}

// Coverage 1 everywhere stays exactly 1, and a frame with no alpha channel gets none.
TEST(Alpha, WholeCoverageStaysWhole) {
    const float grey[3] = {0.5f, 0.5f, 0.5f};
    OIIO::ImageBuf in = scene(40, grey, 0, false), out;
    for (int j = 0; j < kW; ++j)
        for (int i = 0; i < kW; ++i) in.setpixel(i, j, 0, std::array<float, 5>{0.5f, 0.5f, 0.5f, 1.0f, kDepth}.data(), 5);
    ASSERT_TRUE(diffract(out, in, "opaque", options())) << out.geterror();
    for (int j = 0; j < kW; ++j)
        for (int i = 0; i < kW; ++i) ASSERT_EQ(out.getchannel(i, j, 0, 3), 1.0f) << i << "," << j;
}
