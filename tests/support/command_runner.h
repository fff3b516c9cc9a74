// Running the built programs from tests, as a user would, and making small input renders.
#pragma once
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagecache.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace wavecam::test {

struct CommandRun {
    int status;
    std::string output;  // stdout and stderr together
};

inline CommandRun run_command(const std::string& cmd) {
    CommandRun r{0, {}};
    FILE* p = popen((cmd + " 2>&1").c_str(), "r");
    char buf[512];
    while (fgets(buf, sizeof buf, p)) r.output += buf;
    r.status = pclose(p);
    return r;
}

// An image file read whole as float, as it is on disk now (not as OIIO's shared cache last saw
// it: a test writes the same name again); a failure to read it fails the test, naming the file.
inline OIIO::ImageBuf read_float(const std::filesystem::path& path) {
    OIIO::ImageCache::create(true)->invalidate(OIIO::ustring(path.string()), true);
    OIIO::ImageBuf b(path.string());
    EXPECT_TRUE(b.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << path << ": " << b.geterror();
    return b;
}

// A fresh scratch folder per test binary.
inline std::filesystem::path scratch(const std::string& name) {
    auto d = std::filesystem::temp_directory_path() / ("wavecam_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
}

// A w x h render: channels R, G, B, Z with a pattern, depth `z`, fov attribute in degrees.
inline void write_render(const std::string& path, int w, int h, float z, float fov_deg,
                         const std::vector<std::string>& names = {"R", "G", "B", "Z"}) {
    OIIO::ImageSpec spec(w, h, int(names.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = names;
    if (fov_deg > 0) spec.attribute("wavecam.fov", fov_deg);
    OIIO::ImageBuf buf(spec);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            std::vector<float> px(names.size(), 0.0f);
            px[0] = ((i / 2 + j / 2) % 2) ? 1.0f : 0.1f;
            if (names.size() > 1) px[1] = 0.5f;
            if (names.size() > 2) px[2] = float(i) / w;
            if (names.size() > 3) px[3] = z;
            buf.setpixel(i, j, px.data());
        }
    buf.write(path);
}

}  // namespace wavecam::test
