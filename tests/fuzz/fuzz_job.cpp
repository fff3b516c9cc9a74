// Fuzzes a whole job up to its work: a render header with extreme values (any float as the
// field of view and the depth, any size up to 64 x 64) and settings lines "key=value" with
// extreme numbers. Reading, resolving, the camera's range checks and the work and memory
// estimates must end in a named refusal, never a crash, a hang or a huge allocation: the
// limits are set to 1 byte and 1 term, so every job that passes the checks is refused by them
// (issue 26: a pinhole of 1000m, a 2x128 frame, a depth of 1e-40 or fov of 179.999 degrees
// aborted or hung before the checks existed).
#include <OpenImageIO/imagebuf.h>

#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

#include "front/settings.h"
#include "wavecam/diffract_image.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 11) return 0;
    const int w = 1 + data[0] % 64, h = 1 + data[1] % 64;
    float fov, depth;
    std::memcpy(&fov, data + 2, sizeof fov);
    std::memcpy(&depth, data + 6, sizeof depth);
    const bool fov_as_string = data[10] & 1;
    OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "Z"};
    if (fov_as_string) spec.attribute("wavecam.fov", std::to_string(fov) + "deg");
    else spec.attribute("wavecam.fov", fov);
    OIIO::ImageBuf img(spec);
    std::vector<float> px(size_t(w) * h * 4, 0.5f);
    for (size_t p = 0; p < size_t(w) * h; ++p) px[4 * p + 3] = (p % 3 == 0) ? depth : 2.0f;
    img.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());

    std::istringstream in(std::string(reinterpret_cast<const char*>(data + 11), size - 11));
    wavecam::front::SettingSources sources;
    for (std::string line; std::getline(in, line);) {
        const size_t eq = line.find('=');
        sources.given[line.substr(0, eq)] = eq == std::string::npos ? "" : line.substr(eq + 1);
    }
    sources.given_name = [](const std::string& key) { return "--" + key; };
    auto settings = wavecam::front::resolve_settings(img.spec(), sources);
    if (!settings.ok()) {
        if (settings.error.empty()) std::abort();
        return 0;
    }
    wavecam::DiffractOptions opt = settings.value.options;
    opt.max_memory = 1;  // every job that passes the checks stops at its estimate
    opt.max_terms = 1;
    opt.progress = nullptr;
    opt.on_estimate = nullptr;
    wavecam::DiffractPlan plan(opt);
    OIIO::ImageBuf out;
    auto r = plan.diffract(out, img, "fuzz.exr", 1);
    if (r.ok() || r.error.rfind("fuzz.exr: ", 0) != 0) std::abort();
    return 0;
}
