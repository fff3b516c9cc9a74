// Fuzzes the image-to-sources step: bytes become a small float image (R, G, B, Z with a
// field of view) whose values include NaN, Inf, negatives and huge numbers, and whose header has
// any data and display windows; and, written to a file, any parts (names repeated, missing,
// channels lacking) and MIP levels or tiles. Reading it as a render (choosing a part by a name
// from the bytes) and estimating its work must give a result or a named error, never a crash;
// a render read is a frame centred on the display window holding both windows.
//
// Bytes: width, height, fov, flags (bit 0: windows from bytes 4-9; bit 1: through a file;
// bit 2: MIP-mapped; bit 3: tiled; bits 4-5: parts - 1; bits 6-7: the name asked for), data
// window x, y, display window x, y, width, height (signed and unsigned bytes), each part's
// channel mask, then the pixels.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "wavecam/diffract_image.h"

namespace {

const char* const kNames[] = {"", "beauty", "depth", "beauty"};  // (a name twice, a name missing)

void check(bool ok) {
    if (!ok) std::abort();
}

// The render's frame: it holds the data window and the display window, centred on the latter.
void check_frame(const wavecam::RenderInput& in, const OIIO::ImageSpec& spec) {
    const size_t n = size_t(in.width) * in.height;
    check(in.depth.size() == n && in.rgb.size() == 3 * n);
    check(in.x0 <= spec.x && in.y0 <= spec.y && in.x0 + in.width >= spec.x + spec.width &&
          in.y0 + in.height >= spec.y + spec.height);
    if (in.windows.declared) {
        const OIIO::ROI& d = in.windows.display;
        check(in.x0 <= d.xbegin && in.x0 + in.width >= d.xend && in.y0 <= d.ybegin && in.y0 + in.height >= d.yend);
        check(2 * in.x0 + in.width == 2 * d.xbegin + d.width() && 2 * in.y0 + in.height == 2 * d.ybegin + d.height());
    }
    check(in.fov_h > 0 && in.fov_h < M_PI && in.display_fov_h > 0 && in.display_fov_h <= in.fov_h + 1e-12);
}

// The image as a file of `parts` parts, MIP-mapped or tiled; false when OIIO refuses to write it.
bool write_file(const std::string& path, const OIIO::ImageBuf& img, int parts, const uint8_t* masks, bool mip,
                bool tiled) {
    std::vector<OIIO::ImageSpec> specs;
    std::vector<std::vector<int>> channels;
    for (int p = 0; p < parts; ++p) {
        OIIO::ImageSpec spec = img.spec();
        spec.channelnames.clear();
        channels.emplace_back();
        for (int c = 0; c < 4; ++c)
            if (masks[p] & (1 << c) || c == 0) {  // (at least one channel)
                spec.channelnames.push_back(img.spec().channelnames[c]);
                channels.back().push_back(c);
            }
        spec.nchannels = int(spec.channelnames.size());
        spec.z_channel = spec.alpha_channel = -1;
        spec.attribute("oiio:subimagename", kNames[(masks[p] >> 4) % 4]);
        if (tiled || mip) spec.tile_width = spec.tile_height = 4;
        specs.push_back(spec);
    }
    auto out = OIIO::ImageOutput::create(path);
    if (!out) return false;
    bool ok = out->open(path, parts, specs.data());
    for (int p = 0; ok && p < parts; ++p) {
        if (p > 0) ok = out->open(path, specs[p], OIIO::ImageOutput::AppendSubimage);
        for (int level = 0; ok && (level == 0 || (mip && level < 3)); ++level) {
            if (level > 0) {
                specs[p].width = std::max(1, specs[p].width / 2);
                specs[p].height = std::max(1, specs[p].height / 2);
                ok = out->open(path, specs[p], OIIO::ImageOutput::AppendMIPLevel);
            }
            std::vector<float> px;
            for (int y = 0; y < specs[p].height; ++y)
                for (int x = 0; x < specs[p].width; ++x)
                    for (int c : channels[p]) px.push_back(img.getchannel(img.xbegin() + x, img.ybegin() + y, 0, c));
            ok = ok && out->write_image(OIIO::TypeDesc::FLOAT, px.data());
        }
    }
    const bool closed = out->close();
    OIIO::geterror();
    return ok && closed;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    constexpr size_t kHeader = 13;
    if (size < kHeader) return 0;
    const int w = 1 + data[0] % 8, h = 1 + data[1] % 8;
    const float fov = float(data[2]) * 0.75f;  // 0 .. 191 degrees: out-of-range values too
    const uint8_t flags = data[3];
    OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "Z"};
    spec.attribute("wavecam.fov", fov);
    if (flags & 1) {  // any windows: a crop, an overscan, disjoint, empty display
        spec.x = int8_t(data[4]);
        spec.y = int8_t(data[5]);
        spec.full_x = int8_t(data[6]);
        spec.full_y = int8_t(data[7]);
        spec.full_width = data[8] % 17;
        spec.full_height = data[9] % 17;
    }
    OIIO::ImageBuf img(spec);
    std::vector<float> px(size_t(w) * h * 4, 1.0f);
    std::memcpy(px.data(), data + kHeader, std::min(size - kHeader, px.size() * sizeof(float)));
    img.set_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());

    OIIO::ImageBuf read;
    std::string name = "fuzz.exr";
    if (flags & 2) {
        // a name of its own each time: OIIO's image cache keeps the header of a name it has read
        static long count = 0;
        name = "/tmp/wavecam_fuzz_render_" + std::to_string(::getpid()) + "_" + std::to_string(count++) + ".exr";
        const int parts = 1 + (flags >> 4) % 3;
        const bool written = write_file(name, img, parts, data + 10, flags & 4, flags & 8);
        auto r = written ? wavecam::read_render(name, kNames[flags >> 6], 1 << 20)
                         : wavecam::Result<OIIO::ImageBuf>::failure(name + ": not written");
        std::remove(name.c_str());
        if (!r.ok()) {
            check(r.error.rfind(name + ": ", 0) == 0);
            return 0;
        }
        read = std::move(r.value);
    } else {
        read = std::move(img);
    }
    auto r = wavecam::load_render(read, name, {});
    if (!r.ok()) {
        check(r.error.rfind(name + ": ", 0) == 0);
        return 0;
    }
    check_frame(r.value, read.spec());
    if (size_t(r.value.width) * r.value.height > 256) return 0;  // (the estimate's planning: small frames, fast runs)
    wavecam::DiffractOptions opt;
    opt.method = wavecam::DiffractMethod::RandomPhase;
    const double terms = wavecam::estimate_terms(opt, r.value.camera(50e-3), r.value.depth);
    check(terms >= 0);
    return 0;
}
