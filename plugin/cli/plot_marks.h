// Marks that make a picture readable: text, a scale bar in micrometres and log-axis ticks, drawn
// with OpenImageIO's render_text / render_line / render_box (DejaVu Sans, fonts-dejavu-core).
#pragma once
#include <OpenImageIO/imagebuf.h>

#include <array>
#include <string>
#include <vector>

namespace wavecam::cli {

using Colour = std::array<float, 3>;

enum class Align { Left, Centre, Right };

// How text is drawn: its size in pixels, its colour, and whether it starts at, is centred on or
// ends at its x.
struct TextStyle {
    int size;
    Colour colour;
    Align align = Align::Left;
};

// `s` (ASCII: OpenImageIO 2.4 draws bytes, not UTF-8) with its baseline at y, placed at x as `style` aligns it.
void draw_text(OIIO::ImageBuf& img, int x, int y, const std::string& s, const TextStyle& style);

// How wide draw_text draws `s`, in pixels.
int text_width(const std::string& s, int size);

// The largest 1, 2 or 5 x 10^k not above `limit` (> 0).
double nice_below(double limit);

// A bar of a round length in micrometres (at most `max_pixels` long) with its length written
// above its left end ("50 um"); its left end at (x, y). `pitch` is metres per pixel on the film.
void draw_scale_bar(OIIO::ImageBuf& img, int x, int y, double pitch, int max_pixels, const Colour& colour);

// Ticks of a log axis over [lo, hi]: every 1..9 x 10^k inside, `labelled` for 1, 2 and 5 x 10^k,
// also 3, 4, 6 and 8 x 10^k over less than a factor of 12, every one over less than a factor of 3.
struct Tick {
    double value;
    bool labelled;
};
std::vector<Tick> log_ticks(double lo, double hi);

// A number as a tick label: at most four significant digits, no trailing zeros (0.05, 0.2, 150).
std::string tick_label(double value);

}  // namespace wavecam::cli
