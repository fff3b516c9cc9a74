// Fuzzes the image-to-sources step: bytes become a small float image (R, G, B, Z with a
// field of view) whose values include NaN, Inf, negatives and huge numbers; reading it as a
// render and estimating its work must give a result or a named error, never a crash.
#include <OpenImageIO/imagebuf.h>

#include <cstdlib>
#include <cstring>

#include "wavecam/diffract_image.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 3) return 0;
    const int w = 1 + data[0] % 8, h = 1 + data[1] % 8;
    const float fov = float(data[2]) * 0.75f;  // 0 .. 191 degrees: out-of-range values too
    OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "Z"};
    spec.attribute("wavecam.fov", fov);
    OIIO::ImageBuf img(spec);
    std::vector<float> px(size_t(w) * h * 4, 1.0f);
    std::memcpy(px.data(), data + 3, std::min(size - 3, px.size() * sizeof(float)));
    img.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());
    auto r = wavecam::load_render(img, "fuzz.exr", {});
    if (!r.ok()) {
        if (r.error.rfind("fuzz.exr: ", 0) != 0) std::abort();
        return 0;
    }
    wavecam::PinholeCamera cam;
    cam.width = r.value.width;
    cam.height = r.value.height;
    cam.fov_h = r.value.fov_h;
    cam.film_distance = 50e-3;
    wavecam::DiffractOptions opt;
    opt.method = wavecam::DiffractMethod::RandomPhase;
    const double terms = wavecam::estimate_terms(opt, cam, r.value.depth);
    if (!(terms >= 0)) std::abort();
    return 0;
}
