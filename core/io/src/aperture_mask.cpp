#include "wavecam/aperture_mask.h"

#include "wavecam/render_input.h"

namespace wavecam {

Result<Aperture> load_aperture(const std::string& text, const std::string& field) {
    auto parsed = parse_aperture(text, field);
    if (!parsed.ok() || parsed.value.shape != ApertureShape::Mask) return parsed;
    Aperture a = parsed.value;
    const auto read = read_image(a.mask_file);
    if (!read.ok()) return Result<Aperture>::failure(field + ": mask " + read.error);
    const OIIO::ImageBuf& image = read.value;
    const OIIO::ImageSpec& spec = image.spec();
    const int w = spec.width, h = spec.height, nc = spec.nchannels;
    std::vector<float> pixels(size_t(w) * h * nc);
    if (!image.get_pixels(OIIO::ROI(spec.x, spec.x + w, spec.y, spec.y + h), OIIO::TypeDesc::FLOAT, pixels.data()))
        return Result<Aperture>::failure(field + ": mask '" + a.mask_file + "': " + image.geterror());
    const int grey = nc >= 3 ? 3 : 1;  // colour: the mean of R, G, B; alpha is not transmission
    std::vector<float> amplitude(size_t(w) * h);
    for (size_t p = 0; p < amplitude.size(); ++p) {
        float sum = 0;
        for (int k = 0; k < grey; ++k) sum += pixels[p * nc + k];
        amplitude[p] = sum / grey;
    }
    if (auto s = set_aperture_mask(a, w, h, std::move(amplitude), field); !s.ok())
        return Result<Aperture>::failure(s.error);
    return Result<Aperture>::success(a);
}

}  // namespace wavecam
