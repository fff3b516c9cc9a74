#include "compare_sheet.h"

#include <OpenImageIO/color.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>

#include "display_header.h"
#include "wavecam/atomic_write.h"
#include "wavecam/colour_pipeline.h"

namespace wavecam::cli {
namespace {

constexpr const char* kDisplay = "sRGB";
constexpr const char* kView = "Standard";

// R, G, B of an image, through the config's display view.
Result<OIIO::ImageBuf> to_display(const OIIO::ImageBuf& rgb, const std::string& space, OIIO::ColorConfig& cc) {
    OIIO::ImageBuf shown = OIIO::ImageBufAlgo::ociodisplay(rgb, kDisplay, kView, space, "", false, "", "", &cc);
    if (shown.has_error()) return Result<OIIO::ImageBuf>::failure("display view: " + shown.geterror());
    return Result<OIIO::ImageBuf>::success(std::move(shown));
}

OIIO::ImageBuf first_three(const OIIO::ImageBuf& img, const int order[3]) {
    return OIIO::ImageBufAlgo::channels(img, 3, OIIO::cspan<int>(order, 3));
}

void label(OIIO::ImageBuf& img, int x, int panel_width, const std::string& text) {
    const int size = std::max(12, img.spec().height / 20);
    const char* font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    // A missing font only loses the label, never the sheet; so does a panel too small for it
    // (OIIO's text drawing asserts on text beyond the image).
    const OIIO::ROI box = OIIO::ImageBufAlgo::text_size(text, size, font);
    if (!box.defined() || box.width() + 4 > panel_width || size + 2 + box.yend > img.spec().height) return;
    OIIO::ImageBufAlgo::render_text(img, x + 4, size + 2, text, size, font, {1.0f, 1.0f, 0.3f});
    img.geterror();
}

}  // namespace

OIIO::TypeDesc display_format(const std::string& path) {
    const std::string ext = OIIO::Strutil::lower(OIIO::Filesystem::extension(path));
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") return OIIO::TypeDesc::UINT8;
    if (ext == ".tif" || ext == ".tiff") return OIIO::TypeDesc::UINT16;
    return OIIO::TypeDesc::UNKNOWN;
}

Result<bool> write_display_image(const OIIO::ImageBuf& output, const DiffractOptions& opt, const std::string& path) {
    const OIIO::TypeDesc format = display_format(path);
    if (format == OIIO::TypeDesc::UNKNOWN)
        return Result<bool>::failure(path + ": expected a display-referred .png, .jpg or .tif name");
    auto config = load_colour_config(opt.colorconfig);
    if (!config.ok()) return Result<bool>::failure(config.error);
    OIIO::ColorConfig cc(config.value.path());
    const int rgb[3] = {0, 1, 2};
    auto shown = to_display(first_three(output, rgb), output.spec().get_string_attribute("oiio:ColorSpace"), cc);
    if (!shown.ok()) return Result<bool>::failure(path + ": " + shown.error);
    // the header says what the pixels now are: display-encoded RGB, one layer
    OIIO::ImageSpec& spec = shown.value.specmod();
    spec.erase_attribute("BlenderMultiChannel");
    tag_display_encoded(spec);
    spec.attribute("wavecam.display", kDisplay);
    spec.attribute("wavecam.view", kView);
    return write_image_atomically(shown.value, path, format);
}

Result<bool> write_compare_sheet(const OIIO::ImageBuf& input, const OIIO::ImageBuf& output,
                                 const DiffractOptions& opt, const std::string& path) {
    auto config = load_colour_config(opt.colorconfig);
    if (!config.ok()) return Result<bool>::failure(config.error);
    OIIO::ColorConfig cc(config.value.path());
    auto found = find_render_channels(input.spec(), opt.read);
    if (!found.ok()) return Result<bool>::failure(path + ": " + found.error);
    const RenderChannels& ch = found.value;
    const int in_order[3] = {ch.r, ch.g, ch.b}, out_order[3] = {0, 1, 2};
    const std::string in_space = output.spec().get_string_attribute("wavecam.input-colorspace");
    const std::string out_space = output.spec().get_string_attribute("oiio:ColorSpace");
    const OIIO::ImageBuf in_rgb = first_three(input, in_order);
    // the output in the input's space, so the difference compares like with like
    const OIIO::ImageBuf out_rgb = OIIO::ImageBufAlgo::colorconvert(first_three(output, out_order), out_space,
                                                                    in_space, false, "", "", &cc);
    const OIIO::ImageBuf diff = OIIO::ImageBufAlgo::absdiff(in_rgb, out_rgb);
    const int w = input.spec().width, h = input.spec().height;
    OIIO::ImageBuf sheet(OIIO::ImageSpec(3 * w, h, 3, OIIO::TypeDesc::FLOAT));
    const OIIO::ImageBuf* panels[3] = {&in_rgb, &out_rgb, &diff};
    const char* names[3] = {"input (ideal pinhole)", "wavecam", "|difference|"};
    for (int k = 0; k < 3; ++k) {
        auto shown = to_display(*panels[k], in_space, cc);
        if (!shown.ok()) return Result<bool>::failure(path + ": " + shown.error);
        OIIO::ImageBufAlgo::paste(sheet, k * w, 0, 0, 0, shown.value);
        label(sheet, k * w, w, names[k]);
    }
    tag_display_encoded(sheet.specmod());
    return write_image_atomically(sheet, path, OIIO::TypeDesc::UINT8);
}

}  // namespace wavecam::cli
