#include "wavecam/aperture_mask.h"

#include "wavecam/render_input.h"

namespace wavecam {

Result<Aperture> load_aperture(const std::string& text, const std::string& field) {
    auto parsed = parse_aperture(text, field);
    if (!parsed.ok() || parsed.value.shape != ApertureShape::Mask) return parsed;
    Aperture a = parsed.value;
    const auto read = read_image(a.mask_file);
    if (!read.ok()) return Result<Aperture>::failure(field + ": mask " + read.error);
    const OIIO::ImageSpec& spec = read.value.spec();
    const int w = spec.width, h = spec.height;
    const int grey = spec.nchannels >= 3 ? 3 : 1;  // colour: the mean of R, G, B; alpha is not transmission
    std::vector<float> amplitude;
    const OIIO::ROI first_slice(spec.x, spec.x + w, spec.y, spec.y + h);
    for (OIIO::ImageBuf::ConstIterator<float> pixel(read.value, first_slice); !pixel.done(); ++pixel) {
        float sum = 0;
        for (int k = 0; k < grey; ++k) sum += pixel[k];
        amplitude.push_back(sum / grey);
    }
    if (auto s = set_aperture_mask(a, w, h, std::move(amplitude), field); !s.ok())
        return Result<Aperture>::failure(s.error);
    return Result<Aperture>::success(a);
}

}  // namespace wavecam
