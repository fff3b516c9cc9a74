#include "exr_output.h"
#include <OpenImageIO/imageio.h>
#include <cstdio>
#include <unistd.h>

namespace wavecam::trace {

Result<Written> write_exr(const std::string& path, const RenderedImage& image, const ExrHeader& header) {
    OIIO::ImageSpec spec(image.width, image.height, 4, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "Z"};
    spec.z_channel = 3;
    spec.attribute("compression", "zip");
    spec.attribute("wavecam.fov", header.fov_deg);
    spec.attribute("wavecam.depth", "planar");
    spec.attribute("wavecam.scene", header.scene_name);
    spec.attribute("worldToCamera", OIIO::TypeDesc::TypeMatrix44, header.world_to_camera.data());
    for (const auto& [name, value] : header.extra) spec.attribute(name, value);

    std::vector<float> pixels(4 * image.depth.size());
    for (std::size_t p = 0; p < image.depth.size(); ++p) {
        for (int c = 0; c < 3; ++c) pixels[4 * p + c] = image.rgb[3 * p + c];
        pixels[4 * p + 3] = image.depth[p];
    }

    const std::string partial = path + ".partial-" + std::to_string(::getpid());
    auto out = OIIO::ImageOutput::create("exr");
    if (!out) return Error{path + ": OpenImageIO has no OpenEXR writer"};
    bool ok = out->open(partial, spec) && out->write_image(OIIO::TypeDesc::FLOAT, pixels.data());
    ok = out->close() && ok;
    if (!ok) {
        const std::string why = out->geterror();
        std::remove(partial.c_str());
        return Error{path + ": cannot write: " + why};
    }
    if (std::rename(partial.c_str(), path.c_str()) != 0) {
        std::remove(partial.c_str());
        return Error{path + ": cannot move the finished file into place"};
    }
    return Written{};
}

}  // namespace wavecam::trace
