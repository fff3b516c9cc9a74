#include "exr_output.h"
#include <OpenImageIO/imagebuf.h>
#include <filesystem>
#include "wavecam/atomic_write.h"

namespace wavecam::trace {

Result<bool> write_exr(const std::string& path, const RenderedImage& image, const ExrHeader& header) {
    if (std::filesystem::path(path).extension() != ".exr")
        return Result<bool>::failure(path + ": expected an output name ending in .exr");
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

    const OIIO::ImageBuf buffer(spec, pixels.data());
    return write_image_atomically(buffer, path, OIIO::TypeDesc::FLOAT);
}

}  // namespace wavecam::trace
