// Reading what a renderer made: an OpenEXR (or any OIIO-readable image) with linear RGB
// radiance and a depth channel, rendered with an ideal pinhole.
#pragma once
#include <OpenImageIO/imagebuf.h>
#include <string>
#include <vector>
#include "wavecam/pinhole_camera.h"
#include "wavecam/result.h"

namespace wavecam {

struct RenderReadOptions {
    std::string depth_channel = "Z";  // also matches a layer prefix: "ViewLayer.Depth.Z"
    double fov_h = 0;                 // radians; 0 = from the file's metadata
    std::string fov_from = "the fov setting";  // where fov_h came from, for the output's wavecam.fov-from
    double depth_scale = 1.0;         // metres per unit of the depth channel (the depth-scale setting, > 0);
                                      // a value >= 1e9 (or inf) in the file is sky whatever the scale
    std::string subimage;             // the part (OIIO subimage) read, by name; "" = the file's only one
    std::string layer;                // the radiance layer ("ViewLayer.Combined", "beauty"); "" = the one
                                      // the file's names make plain (render_layers.cpp)
    bool clamp_negative = false;      // negative radiance and alpha set to 0 (and counted) instead of refused
    bool diffract_again = false;      // a file wavecam wrote (wavecam.method in its header) taken as a render
};

// Where the file's pixels lie on the camera's frame. OpenEXR's display window is the frame the
// camera saw: its centre is the optical axis and the field of view (--fov, wavecam.fov) spans its
// width. The data window holds the pixels: a crop of the frame (a compositor's bounding box) or
// the frame and an overscan margin beyond it.
struct FrameWindows {
    bool declared = false;  // the file's data window differs from its display window
    OIIO::ROI data, display;  // the file's pixel coordinates
};

// The render's channels (-1 where missing). The radiance layer is chosen as a whole: the layer
// given, else the only one holding R, G and B, else the unnamed layer, else the one named
// Combined or beauty; several candidates are refused, naming them. Its A is the alpha. Depth is
// `depth_channel` in full, else in the radiance layer, else in its view layer ("ViewLayer.Depth.Z"
// beside "ViewLayer.Combined.R"), else unnamed (render_layers.cpp).
struct RenderChannels {
    std::string layer;  // the radiance layer: "" (R, G, B), "beauty", "ViewLayer.Combined"
    int r = -1, g = -1, b = -1, depth = -1;
    int alpha = -1;  // "<layer>.A", optional
};

// What a file's header says about its colour: oiio:ColorSpace, OpenEXR's chromaticities (x, y
// of red, green, blue and white; empty when absent) and the ACES container flag.
struct FileColour {
    std::string colorspace;
    std::vector<float> chromaticities;
    bool aces_container = false;
};

// Radiance and depth as plain arrays, plus what the file says about itself.
struct RenderInput {
    // The frame the camera images: the data window, widened where needed to hold the display
    // window and be centred on it (the widening continues the data window's edge, as beyond any frame).
    int width = 0, height = 0;
    int x0 = 0, y0 = 0;        // the file's pixel coordinates of the frame's pixel (0, 0)
    FrameWindows windows;
    std::vector<float> rgb;    // interleaved R, G, B
    std::vector<float> depth;  // metres (the file's values times RenderReadOptions::depth_scale)
    std::vector<float> alpha;  // the radiance layer's coverage A (premultiplied RGB); empty without one
    size_t clamped = 0;        // negative radiance and alpha values set to 0 (RenderReadOptions::clamp_negative)
    bool premultiplied_on_reading = false;  // the file's alpha was unassociated: RGB multiplied by A on reading
    double fov_h = 0;          // radians, across `width` (the display window's as given, widened with the frame)
    double display_fov_h = 0;  // radians, across the display window (= fov_h for a file without windows)
    std::string fov_from;      // the setting or the attribute it came from
    FileColour colour;         // the radiance's colour space as the file's header gives it
    std::string depth_channel; // the channel actually used
    RenderChannels channels;   // the file's channels read as the render (their indices in its header)

    // The ideal camera the render was made with, its film `film_distance` behind the pinhole.
    PinholeCamera camera(double film_distance) const { return {width, height, fov_h, film_distance}; }
};

// The attribute our tracer, our Blender add-on (and any renderer that wants to) writes:
// horizontal field of view in degrees, as a float, an int or a string ("40", "40deg",
// "0.7rad"). Without it, the field of view must be given.
constexpr const char* kFovAttribute = "wavecam.fov";
// What a harness writes when it has scaled the depth channel to metres itself (render_pov.sh
// --depth-scale 1cm writes "0.01m"): the depth-scale setting is then refused.
constexpr const char* kSceneUnitAttribute = "wavecam.scene-unit";

// The render's channels in a header, as RenderChannels describes them; ambiguous layers or depth
// channels refused, naming the candidates.
Result<RenderChannels> find_render_channels(const OIIO::ImageSpec& spec, const RenderReadOptions& opt);

// Finds R, G, B and the depth channel in `image` (exact names first, then a layer prefix such
// as "ViewLayer.Combined.R", "ViewLayer.Depth.Z") and checks every value. Errors name the
// file, the channel or field, and what was expected.
Result<RenderInput> load_render(const OIIO::ImageBuf& image, const std::string& name, const RenderReadOptions& opt);

// Reads a render: the file's only part (OIIO subimage), else the one named `subimage`; a file of
// several parts and no name (or a name it lacks) is refused, naming its parts and their channels.
// MIP levels past the first are not read (the full-resolution image is level 0).
Result<OIIO::ImageBuf> read_render(const std::string& path, const std::string& subimage,
                                   double max_bytes = 16.0 * (1ull << 30));

// Reads a whole image file (a render, a mask, a share file) through OpenImageIO as float; the
// one reader every front and command uses. Errors read "PATH: cannot be read as an image (OIIO's reason)".
// An image whose header says its pixels need more than `max_bytes` as float is refused before
// they are read (a forged or corrupt header: 60000 x 60000 pixels in a 7 MB file); a name that
// is on disk but no regular file (a FIFO, a device, a folder) before it is opened.
Result<OIIO::ImageBuf> read_image(const std::string& path, double max_bytes = 16.0 * (1ull << 30), int subimage = 0);

}  // namespace wavecam
