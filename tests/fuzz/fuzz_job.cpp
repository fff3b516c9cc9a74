// Fuzzes a whole job up to its work: a render header with extreme values (any float as the
// field of view and the depth, any size up to 64 x 64) and settings lines "key=value" with
// extreme numbers. Reading, resolving, the camera's range checks and the work and memory
// estimates must end in a named refusal, never a crash, a hang or a huge allocation: the
// limits are set to 1 byte and 1 term, so every job that passes the checks is refused by them
// (a pinhole of 1000m, a 2x128 frame, a depth of 1e-40 or fov of 179.999 degrees
// aborted or hung before the checks existed).
#include <OpenImageIO/imagebuf.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
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
    static const float fovs[] = {1e-30f, 0.01f, 1.0f, 30.0f, 90.0f, 151.0f, 170.0f, 179.999f};
    if (data[10] & 4) fov = fovs[data[2] % std::size(fovs)];
    static const float near[] = {1e-40f, 1e-30f, 1e-6f, 3e-3f, 0.01f, 2.0f, 1e9f, 3e38f};
    if (data[10] & 8) depth = near[data[6] % std::size(near)];
    OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "Z"};
    if (fov_as_string) spec.attribute("wavecam.fov", std::to_string(fov) + "deg");
    else spec.attribute("wavecam.fov", fov);
    OIIO::ImageBuf img(spec);
    std::vector<float> px(size_t(w) * h * 4, 0.5f);
    for (size_t p = 0; p < size_t(w) * h; ++p) px[4 * p + 3] = (p % 3 == 0) ? depth : 2.0f;
    img.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());

    // the rest: text lines "key=value" (flag bit 2), else pairs of bytes choosing a key and one
    // of its extreme values (the unit parser is fuzzed on its own; here the values must reach
    // the camera's checks)
    wavecam::front::SettingSources sources;
    if (data[10] & 2) {
        std::istringstream in(std::string(reinterpret_cast<const char*>(data + 11), size - 11));
        for (std::string line; std::getline(in, line);) {
            const size_t eq = line.find('=');
            sources.given[line.substr(0, eq)] = eq == std::string::npos ? "" : line.substr(eq + 1);
        }
    } else {
        static const char* const lengths[] = {"1nm", "0.5um", "681nm", "1um", "0.2mm", "0.3mm", "26mm", "1000m",
                                              "1e300m", "1e-300m", "1e-40m", "inf", "3e38m", "50mm"};
        static const char* const angles[] = {"1e-30deg", "0.01deg", "1deg", "50deg", "151deg", "170deg",
                                             "179.999deg", "1e300rad", "-5deg"};
        static const char* const counts[] = {"0", "1", "2", "3", "16", "1000", "100000", "99999999999"};
        static const char* const lists[] = {"1nm,2nm", "400nm,700nm", "1m,2m", "1e-40nm", "550nm", "10um"};
        static const char* const methods[] = {"convolution", "random-phase", "incoherent"};
        static const char* const apertures[] = {"circle", "square", "polygon:3", "polygon:100000", "zoneplate:1",
                                                "zoneplate:100000", "sieve:3", "sieve:1000:0.1x:1%", "polygon:6:1e300deg"};
        static const char* const depths[] = {"planar", "ray"};
        static const char* const bools[] = {"true", "false"};
        struct Key {
            const char* key;
            const char* const* values;
            size_t count;
        };
        static const Key keys[] = {{"pinhole", lengths, std::size(lengths)},
                                   {"film-distance", lengths, std::size(lengths)},
                                   {"fov", angles, std::size(angles)},
                                   {"wavelengths", counts, std::size(counts)},
                                   {"wavelengths", lists, std::size(lists)},
                                   {"runs", counts, std::size(counts)},
                                   {"film-subsamples", counts, std::size(counts)},
                                   {"overscan", counts, std::size(counts)},
                                   {"method", methods, std::size(methods)},
                                   {"aperture", apertures, std::size(apertures)},
                                   {"depth", depths, std::size(depths)},
                                   {"monochrome", bools, std::size(bools)}};
        for (size_t k = 11; k + 1 < size; k += 2) {
            const Key& key = keys[data[k] % std::size(keys)];
            sources.given[key.key] = key.values[data[k + 1] % key.count];
        }
    }
    sources.given_name = [](const std::string& key) { return "--" + key; };
    auto settings = wavecam::front::resolve_settings(img.spec(), sources);
    const bool print = std::getenv("FUZZ_JOB_PRINT");  // each input's refusal, to see what is reached
    if (!settings.ok()) {
        if (print) std::fprintf(stderr, "settings: %s\n", settings.error.c_str());
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
    if (print) std::fprintf(stderr, "job: %s\n", r.error.c_str());
    if (r.ok() || r.error.rfind("fuzz.exr: ", 0) != 0) std::abort();
    return 0;
}
