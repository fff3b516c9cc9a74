// EXRs as compositors write them, through `wavecam apply`: a crop (data window inside the
// display window) is diffracted as that part of the frame, an overscan margin (data window
// beyond the display window) is read from the file, MIP-mapped and tiled inputs give complete
// outputs, and a file of several parts is read by the part's name or refused naming them.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>

#include "command_runner.h"

namespace fs = std::filesystem;
using namespace wavecam::test;

namespace {
const std::string kWavecam = WAVECAM_BINARY;
// the default method (convolution); a PSF of a few pixels on a 96-pixel frame
const std::string kSettings = " --film-distance 20mm --pinhole 0.2mm --wavelengths 3 ";
constexpr float kFovDeg = 40.0f;

// The scene at file pixel (x, y) of a frame: R, G, B and Z (two depths), detail everywhere.
void scene_pixel(int x, int y, float px[4]) {
    px[0] = ((x / 6 + y / 6) % 2) ? 1.0f : 0.15f;
    px[1] = 0.5f + 0.4f * std::sin(0.37f * x + 0.11f * y);
    px[2] = 0.2f + 0.006f * float(((x * 7 + y * 3) % 100 + 100) % 100);
    px[3] = x < y ? 2.0f : 4.0f;
}

// The scene's pixels over `data`, the header's display window `display` and field of view.
void write_windowed(const std::string& path, const OIIO::ROI& data, const OIIO::ROI& display, float fov_deg) {
    OIIO::ImageSpec spec(data.width(), data.height(), 4, OIIO::TypeDesc::FLOAT);
    spec.x = data.xbegin;
    spec.y = data.ybegin;
    spec.full_x = display.xbegin;
    spec.full_y = display.ybegin;
    spec.full_width = display.width();
    spec.full_height = display.height();
    spec.channelnames = {"R", "G", "B", "Z"};
    spec.attribute("wavecam.fov", fov_deg);
    OIIO::ImageBuf buf(spec);
    for (int y = data.ybegin; y < data.yend; ++y)
        for (int x = data.xbegin; x < data.xend; ++x) {
            float px[4];
            scene_pixel(x, y, px);
            buf.setpixel(x, y, px);
        }
    ASSERT_TRUE(buf.write(path)) << buf.geterror();
}

OIIO::ImageBuf read(const fs::path& p) {
    OIIO::ImageBuf b(p.string());
    EXPECT_TRUE(b.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << p << b.geterror();
    return b;
}

void apply(const fs::path& in, const fs::path& out, const std::string& extra = "") {
    const auto r = run_command(kWavecam + " apply " + in.string() + " -o " + out.string() + kSettings + extra);
    ASSERT_EQ(r.status, 0) << r.output;
}

double peak(const OIIO::ImageBuf& b) {
    const auto stats = OIIO::ImageBufAlgo::computePixelStats(b);
    return *std::max_element(stats.max.begin(), stats.max.begin() + 3);
}

// Largest |a - b| over R, G, B at the file pixels of `region`, read at (x + dx, y + dy) in b.
double worst_difference(const OIIO::ImageBuf& a, const OIIO::ImageBuf& b, const OIIO::ROI& region, int dx = 0,
                        int dy = 0) {
    double worst = 0;
    for (int y = region.ybegin; y < region.yend; ++y)
        for (int x = region.xbegin; x < region.xend; ++x)
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, double(std::fabs(a.getchannel(x, y, 0, c) - b.getchannel(x + dx, y + dy, 0, c))));
    return worst;
}

OIIO::ROI inset(const OIIO::ROI& r, int by) { return {r.xbegin + by, r.xend - by, r.ybegin + by, r.yend - by}; }
}  // namespace

// A crop keeps its windows, and its interior (away from its edges, where light from outside the
// crop is missing) is the full frame's result at the same pixels, within 1% of the peak: for a
// centred crop and an off-axis one. The off-axis crop read as a frame of its own (the same pixel
// pitch, its centre taken as the axis: wrong field angles) misses by more, so the bound can fail.
TEST(ExrWindows, ACropIsDiffractedAsThatPartOfTheFrame) {
    const fs::path dir = scratch("exr_crop");
    const OIIO::ROI frame(0, 96, 0, 96);
    write_windowed((dir / "full.exr").string(), frame, frame, kFovDeg);
    apply(dir / "full.exr", dir / "full_out.exr");
    const OIIO::ImageBuf full = read(dir / "full_out.exr");
    const double top = peak(full);
    constexpr int kInset = 8;  // beyond the PSF's reach from the crop's edge
    for (const OIIO::ROI crop : {OIIO::ROI(24, 72, 24, 72), OIIO::ROI(4, 44, 8, 40)}) {
        SCOPED_TRACE("crop x " + std::to_string(crop.xbegin) + ".." + std::to_string(crop.xend - 1));
        // a name of its own per crop: OIIO's image cache may hand back a file rewritten under
        // the same name within its clock's resolution as it first read it
        const std::string name = "crop" + std::to_string(crop.xbegin);
        write_windowed((dir / (name + ".exr")).string(), crop, frame, kFovDeg);
        apply(dir / (name + ".exr"), dir / (name + "_out.exr"));
        const OIIO::ImageBuf out = read(dir / (name + "_out.exr"));
        const OIIO::ImageSpec& s = out.spec();
        EXPECT_EQ(OIIO::ROI(s.x, s.x + s.width, s.y, s.y + s.height), crop);
        EXPECT_EQ(OIIO::ROI(s.full_x, s.full_x + s.full_width, s.full_y, s.full_y + s.full_height), frame);
        EXPECT_NEAR(s.get_float_attribute("wavecam.fov"), kFovDeg, 1e-4);  // the display window's
        const double worst = worst_difference(out, full, inset(crop, kInset));
        std::printf("crop (%d, %d)-(%d, %d): interior within %.3g%% of the full frame's peak\n", crop.xbegin,
                    crop.ybegin, crop.xend - 1, crop.yend - 1, 100 * worst / top);
        EXPECT_LT(worst, 0.01 * top);
        if (crop.xbegin != 24) {  // the off-axis crop as a frame centred on its own middle
            const float own_fov =
                float(2 * std::atan(std::tan(0.5 * kFovDeg * M_PI / 180) * crop.width() / 96.0) * 180 / M_PI);
            const OIIO::ROI alone(0, crop.width(), 0, crop.height());
            OIIO::ImageBuf shifted;
            ASSERT_TRUE(OIIO::ImageBufAlgo::cut(shifted, read(dir / (name + ".exr"))));  // origin (0, 0), no windows
            shifted.specmod().attribute("wavecam.fov", own_fov);
            ASSERT_TRUE(shifted.write((dir / "alone.exr").string()));
            apply(dir / "alone.exr", dir / "alone_out.exr");
            const double wrong =
                worst_difference(read(dir / "alone_out.exr"), full, inset(alone, kInset), crop.xbegin, crop.ybegin);
            std::printf("  the same pixels on their own axis: %.3g%% of the peak\n", 100 * wrong / top);
            EXPECT_GT(wrong, 0.02 * top);
        }
    }
    fs::remove_all(dir);
}

// Overscan read from the file: a data window 8 pixels beyond a 64x64 display window is the same
// camera as the same 80x80 pixels as a plain image with the fov of the whole (float rounding
// apart), and over the display window what they give with --overscan 8, within 1% of the peak:
// that run lays the convolution's PSF anchors over the 64-pixel frame it outputs, the windowed
// file over all 80 pixels it outputs. The output keeps both windows.
TEST(ExrWindows, OverscanIsReadFromTheFilesWindows) {
    const fs::path dir = scratch("exr_overscan");
    const OIIO::ROI display(0, 64, 0, 64), data(-8, 72, -8, 72);
    const double whole_fov = 2 * std::atan(std::tan(0.5 * kFovDeg * M_PI / 180) * 80 / 64) * 180 / M_PI;
    write_windowed((dir / "over.exr").string(), data, display, kFovDeg);
    apply(dir / "over.exr", dir / "over_out.exr");
    // the same pixels as a plain 80x80 image at (0, 0)
    OIIO::ImageBuf plain;
    ASSERT_TRUE(OIIO::ImageBufAlgo::cut(plain, read(dir / "over.exr")));
    ASSERT_TRUE(plain.write((dir / "plain.exr").string()));
    char fov[64];
    std::snprintf(fov, sizeof fov, " --fov %.12gdeg", whole_fov);
    apply(dir / "plain.exr", dir / "plain_out.exr", std::string(" --overscan 8") + fov);
    apply(dir / "plain.exr", dir / "whole_out.exr", fov);

    const OIIO::ImageBuf over = read(dir / "over_out.exr"), flagged = read(dir / "plain_out.exr");
    const double same = worst_difference(over, read(dir / "whole_out.exr"), data, 8, 8);
    EXPECT_LT(same, 1e-5 * peak(flagged));
    const OIIO::ImageSpec& s = over.spec();
    EXPECT_EQ(OIIO::ROI(s.x, s.x + s.width, s.y, s.y + s.height), data);
    EXPECT_EQ(OIIO::ROI(s.full_x, s.full_x + s.full_width, s.full_y, s.full_y + s.full_height), display);
    ASSERT_EQ(flagged.spec().width, 64);
    EXPECT_NEAR(s.get_float_attribute("wavecam.fov"), flagged.spec().get_float_attribute("wavecam.fov"), 1e-3);
    const double worst = worst_difference(over, flagged, display);  // (the flagged run's origin is the display's)
    std::printf("overscan from the windows vs --overscan: %.3g%% of the peak\n", 100 * worst / peak(flagged));
    EXPECT_LT(worst, 0.01 * peak(flagged));

    // the file says what is overscan: the setting as well is refused
    const auto r = run_command(kWavecam + " apply " + (dir / "over.exr").string() + " -o " +
                               (dir / "x.exr").string() + kSettings + " --overscan 8");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("declares its own windows"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "x.exr"));
    fs::remove_all(dir);
}

// A MIP-mapped texture (what oiiotool -otex and maketx write) and a tiled image give the output
// a scanline input gives, pixel for pixel, as one level that OIIO reads whole.
TEST(ExrWindows, MipMappedAndTiledInputsGiveCompleteOutputs) {
    const fs::path dir = scratch("exr_levels");
    const OIIO::ROI frame(0, 48, 0, 40);
    write_windowed((dir / "plain.exr").string(), frame, frame, kFovDeg);
    apply(dir / "plain.exr", dir / "plain_out.exr");
    const OIIO::ImageBuf plain = read(dir / "plain.exr");
    OIIO::ImageSpec config;
    ASSERT_TRUE(OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, plain,
                                                 (dir / "mip.exr").string(), config));
    OIIO::ImageBuf tiled = read(dir / "plain.exr");
    tiled.set_write_tiles(16, 16);
    ASSERT_TRUE(tiled.write((dir / "tiled.exr").string()));
    const OIIO::ImageBuf expected = read(dir / "plain_out.exr");
    for (const std::string name : {"mip", "tiled"}) {
        SCOPED_TRACE(name);
        auto in = OIIO::ImageInput::open((dir / (name + ".exr")).string());
        ASSERT_TRUE(in);
        EXPECT_EQ(in->seek_subimage(0, 1), name == "mip");  // the input has levels past 0, or not
        in.reset();
        apply(dir / (name + ".exr"), dir / (name + "_out.exr"));
        auto out = OIIO::ImageInput::open((dir / (name + "_out.exr")).string());
        ASSERT_TRUE(out);
        EXPECT_FALSE(out->seek_subimage(0, 1)) << "the output declares a level it does not hold";
        EXPECT_EQ(out->spec().tile_width, 0);
        EXPECT_TRUE(out->spec().find_attribute("textureformat") == nullptr);
        std::vector<float> px(size_t(48) * 40 * 4);
        ASSERT_TRUE(out->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, px.data())) << out->geterror();
        out.reset();
        const auto cmp = OIIO::ImageBufAlgo::compare(read(dir / (name + "_out.exr")), expected, 0, 0);
        EXPECT_EQ(cmp.nfail, 0u);
        EXPECT_EQ(cmp.maxerror, 0.0);
    }
    fs::remove_all(dir);
}

namespace {
// Parts of one file, each a name and its channels (filled with the scene's values by position).
void write_parts(const std::string& path, const std::vector<std::pair<std::string, std::vector<std::string>>>& parts) {
    std::vector<OIIO::ImageSpec> specs;
    for (const auto& [name, channels] : parts) {
        OIIO::ImageSpec spec(24, 20, int(channels.size()), OIIO::TypeDesc::FLOAT);
        spec.channelnames = channels;
        spec.attribute("oiio:subimagename", name);
        spec.attribute("wavecam.fov", kFovDeg);
        specs.push_back(spec);
    }
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, int(specs.size()), specs.data())) << OIIO::geterror();
    for (size_t s = 0; s < specs.size(); ++s) {
        if (s > 0) {
            ASSERT_TRUE(out->open(path, specs[s], OIIO::ImageOutput::AppendSubimage));
        }
        std::vector<float> px;
        for (int y = 0; y < 20; ++y)
            for (int x = 0; x < 24; ++x) {
                float v[4];
                scene_pixel(x, y, v);
                for (const std::string& c : specs[s].channelnames) px.push_back(v[c == "Z" ? 3 : c == "R" ? 0 : c == "G" ? 1 : 2]);
            }
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    }
    ASSERT_TRUE(out->close());
}
}  // namespace

// A two-part file: the one part holding R, G, B and Z is diffracted, the other passes through
// unchanged in its place; two parts that could be the render are refused without a name, naming
// both and their channels; chosen by name (--subimage), the part gives what the same pixels give
// as a file of their own; a name it lacks is refused naming the parts. Z in another part than
// R, G, B: said, with how to join them.
TEST(ExrWindows, SeveralPartsAreChosenByNameOrRefusedNamingThem) {
    const fs::path dir = scratch("exr_parts");
    const std::string two = (dir / "two.exr").string(), out = (dir / "out.exr").string();
    write_parts(two, {{"beauty", {"R", "G", "B", "Z"}}, {"notes", {"R", "G", "B"}}});
    write_parts((dir / "one.exr").string(), {{"beauty", {"R", "G", "B", "Z"}}});
    apply(fs::path(two), fs::path(out));
    apply(dir / "one.exr", dir / "one_out.exr");
    {
        OIIO::ImageBuf beauty(out, 0, 0), notes(out, 1, 0), notes_in(two, 1, 0);
        ASSERT_TRUE(beauty.read(0, 0, true, OIIO::TypeDesc::FLOAT) && notes.read(1, 0, true, OIIO::TypeDesc::FLOAT) &&
                    notes_in.read(1, 0, true, OIIO::TypeDesc::FLOAT));
        EXPECT_EQ(notes.spec().get_string_attribute("oiio:subimagename"), "notes");
        EXPECT_EQ(OIIO::ImageBufAlgo::compare(beauty, read(dir / "one_out.exr"), 0, 0).nfail, 0u);
        EXPECT_EQ(OIIO::ImageBufAlgo::compare(notes, notes_in, 0, 0).nfail, 0u);  // passed through
    }
    const std::string pair = (dir / "pair.exr").string();
    write_parts(pair, {{"left", {"R", "G", "B", "Z"}}, {"right", {"R", "G", "B", "Z"}}});
    const std::string out2 = (dir / "out2.exr").string();
    auto r = run_command(kWavecam + " apply " + pair + " -o " + out2 + kSettings);
    EXPECT_EQ(r.status, 2 << 8) << r.output;
    EXPECT_NE(r.output.find("\"left\" (R, G, B, Z), \"right\" (R, G, B, Z)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--subimage"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out2));
    r = run_command(kWavecam + " apply " + two + " -o " + out + kSettings + " --subimage nope");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("none is named \"nope\""), std::string::npos) << r.output;

    apply(fs::path(pair), fs::path(out), " --subimage right");
    const OIIO::ImageBuf right(out, 1, 0);
    EXPECT_EQ(OIIO::ImageBufAlgo::compare(right, read(dir / "one_out.exr"), 0, 0).nfail, 0u);

    const std::string split = (dir / "split.exr").string();
    write_parts(split, {{"rgb", {"R", "G", "B"}}, {"depth", {"Z"}}});
    r = run_command(kWavecam + " apply " + split + " -o " + out + kSettings);
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("R, G, B are in \"rgb\", Z in \"depth\""), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--chappend"), std::string::npos) << r.output;
    r = run_command(kWavecam + " apply " + split + " -o " + out + kSettings + " --subimage rgb");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("channel 'Z' is in part \"depth\""), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("--depth-channel"), std::string::npos) << "naming a depth channel cannot help: " << r.output;
    fs::remove_all(dir);
}
