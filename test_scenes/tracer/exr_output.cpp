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

    OIIO::ImageBuf buffer(spec);
    buffer.set_pixels(OIIO::ROI(0, image.width, 0, image.height, 0, 1, 0, 3), OIIO::TypeDesc::FLOAT, image.rgb.data());
    buffer.set_pixels(OIIO::ROI(0, image.width, 0, image.height, 0, 1, 3, 4), OIIO::TypeDesc::FLOAT, image.depth.data());
    return write_image_atomically(buffer, path, OIIO::TypeDesc::FLOAT);
}

}  // namespace wavecam::trace
