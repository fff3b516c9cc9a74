// What `wavecam apply` writes: the input's layer names, alpha and depth kept;
// display-referred formats through the display view, RGB only, or refused; the field of view
// read in any type; no stale camera headers; header values that say what was used.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebufalgo.h>
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <vector>

#include "command_runner.h"

namespace fs = std::filesystem;
using namespace wavecam::test;

namespace {
const std::string kWavecam = WAVECAM_BINARY;
const std::string kQuick = " --film-distance 20mm --pinhole 0.2mm --wavelengths 3 ";
const std::vector<std::string> kBlenderChannels = {"ViewLayer.Combined.R", "ViewLayer.Combined.G",
                                                   "ViewLayer.Combined.B", "ViewLayer.Combined.A",
                                                   "ViewLayer.Depth.Z"};

// A Blender-like multilayer render: alpha varying over the frame, depth 3 m, and the header a
// Cycles render carries (Lens, cycles.*), camera matrices, and a stale wavecam.runs.
void write_blender_render(const std::string& path, int w, int h) {
    OIIO::ImageSpec spec(w, h, 5, OIIO::TypeDesc::FLOAT);
    spec.channelnames = kBlenderChannels;
    spec.alpha_channel = 3;
    spec.attribute("BlenderMultiChannel", "Blender V2.55.1 and newer");
    spec.attribute("Lens", "50.00 mm");
    spec.attribute("cycles.ViewLayer.samples", "4");
    spec.attribute("Scene", "Scene");
    spec.attribute("wavecam.runs", 16);
    spec.attribute("wavecam.fov", 30.0f);
    const float m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    spec.attribute("worldToCamera", OIIO::TypeDesc::TypeMatrix44, m);
    spec.attribute("worldToNDC", OIIO::TypeDesc::TypeMatrix44, m);
    OIIO::ImageBuf buf(spec);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const float a = float(i + j * w) / float(w * h);
            const float px[5] = {((i / 2 + j / 2) % 2) ? 0.9f : 0.05f, 0.4f, 0.2f, a, 3.0f};
            buf.setpixel(i, j, px);
        }
    ASSERT_TRUE(buf.write(path));
}

OIIO::ImageBuf read(const fs::path& p) {
    OIIO::ImageBuf b(p.string());
    EXPECT_TRUE(b.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << p << ": " << b.geterror();
    return b;
}

// IEC 61966-2-1: the sRGB encoding of a linear value (what the config's sRGB display's
// Standard view does to linear Rec.709), clamped to [0, 1].
float srgb_encode(float v) {
    v = std::min(1.0f, std::max(0.0f, v));
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

CommandRun apply(const fs::path& in, const fs::path& out, const std::string& extra = "") {
    return run_command(kWavecam + " apply " + in.string() + " -o " + out.string() + kQuick + extra);
}
}  // namespace

TEST(OutputFiles, BlenderLayerNamesAndDepthComeBackUnchanged) {
    const fs::path dir = scratch("out_blender");
    write_blender_render((dir / "in.exr").string(), 16, 12);
    const auto r = apply(dir / "in.exr", dir / "out.exr");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageBuf in = read(dir / "in.exr"), out = read(dir / "out.exr");
    EXPECT_EQ(out.spec().channelnames, kBlenderChannels);
    EXPECT_EQ(out.spec().alpha_channel, 3);
    EXPECT_EQ(out.spec().get_string_attribute("BlenderMultiChannel"), "Blender V2.55.1 and newer");
    for (int j = 0; j < 12; ++j)
        for (int i = 0; i < 16; ++i) {
            // alpha is diffracted with the light: a ramp linear over the frame (i/192 + j/12) stays
            // itself under a PSF that is symmetric and sums to one
            EXPECT_NEAR(out.getchannel(i, j, 0, 3), in.getchannel(i, j, 0, 3), 0.01) << i << "," << j;
            EXPECT_EQ(out.getchannel(i, j, 0, 4), 3.0f);  // depth
        }
    // the radiance was diffracted, not copied: the checkerboard's contrast is lower
    float in_max = 0, out_max = 0;
    for (int i = 0; i < 16; ++i) {
        in_max = std::max(in_max, in.getchannel(i, 6, 0, 0));
        out_max = std::max(out_max, out.getchannel(i, 6, 0, 0));
    }
    EXPECT_LT(out_max, in_max);
    fs::remove_all(dir);
}

TEST(OutputFiles, StaleCameraHeadersAreDroppedAndValuesSayWhatWasUsed) {
    const fs::path dir = scratch("out_headers");
    write_blender_render((dir / "in.exr").string(), 8, 8);
    auto r = apply(dir / "in.exr", dir / "fast.exr");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageSpec fast = read(dir / "fast.exr").spec();
    for (const char* stale : {"Lens", "cycles.ViewLayer.samples", "worldToCamera", "worldToNDC", "wavecam.runs",
                              "wavecam.seed", "wavecam.jitter", "wavecam.film-subsamples"})
        EXPECT_EQ(fast.find_attribute(stale), nullptr) << stale;
    EXPECT_EQ(fast.get_string_attribute("Scene"), "Scene");  // not about the camera: kept
    EXPECT_EQ(fast.get_string_attribute("wavecam.method"), "convolution");
    EXPECT_NE(fast.get_string_attribute("wavecam.fov-from").find("wavecam.fov"), std::string::npos)
        << fast.get_string_attribute("wavecam.fov-from");
    EXPECT_FLOAT_EQ(fast.get_float_attribute("wavecam.fov"), 30.0f);

    r = apply(dir / "in.exr", dir / "exact.exr", "--method random-phase --runs 3 --fov 25deg");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageSpec exact = read(dir / "exact.exr").spec();
    EXPECT_EQ(exact.get_int_attribute("wavecam.runs"), 3);
    EXPECT_EQ(exact.get_string_attribute("wavecam.fov-from"), "--fov");
    EXPECT_FLOAT_EQ(exact.get_float_attribute("wavecam.fov"), 25.0f);
    fs::remove_all(dir);
}

TEST(OutputFiles, FieldOfViewIsReadAsFloatIntOrStringWithUnit) {
    const fs::path dir = scratch("out_fov");
    write_render((dir / "base.exr").string(), 8, 8, 2.0f, 0.0f);
    OIIO::ImageBuf base = read(dir / "base.exr");
    struct Case {
        const char* name;
        OIIO::ParamValue value;
        float degrees;  // 0: refused
    } cases[] = {
        {"int", OIIO::ParamValue("wavecam.fov", 40), 40.0f},
        {"float", OIIO::ParamValue("wavecam.fov", 40.5f), 40.5f},
        {"bare", OIIO::ParamValue("wavecam.fov", "40"), 40.0f},
        {"deg", OIIO::ParamValue("wavecam.fov", "40deg"), 40.0f},
        {"rad", OIIO::ParamValue("wavecam.fov", "0.5rad"), float(0.5 * 180 / M_PI)},
        {"word", OIIO::ParamValue("wavecam.fov", "wide"), 0.0f},
        {"zero", OIIO::ParamValue("wavecam.fov", 0), 0.0f},
    };
    for (const Case& c : cases) {
        OIIO::ImageBuf in = base;
        in.specmod().attribute(c.value.name(), c.value.type(), c.value.data());
        const fs::path src = dir / (std::string(c.name) + ".exr"), dst = dir / (std::string(c.name) + "_out.exr");
        ASSERT_TRUE(in.write(src.string()));
        const auto r = apply(src, dst);
        if (c.degrees == 0) {
            EXPECT_NE(r.status, 0) << c.name;
            EXPECT_NE(r.output.find("wavecam.fov"), std::string::npos) << c.name << ": " << r.output;
            EXPECT_FALSE(fs::exists(dst)) << c.name;
            continue;
        }
        ASSERT_EQ(r.status, 0) << c.name << ": " << r.output;
        EXPECT_NEAR(read(dst).spec().get_float_attribute("wavecam.fov"), c.degrees, 1e-4) << c.name;
    }
    fs::remove_all(dir);
}

TEST(OutputFiles, BlenderFileWithoutFieldOfViewToldWhatToDo) {
    const fs::path dir = scratch("out_nofov");
    write_blender_render((dir / "in.exr").string(), 8, 8);
    OIIO::ImageBuf in = read(dir / "in.exr");
    in.specmod().erase_attribute("wavecam.fov");
    ASSERT_TRUE(in.write((dir / "nofov.exr").string()));
    const auto r = apply(dir / "nofov.exr", dir / "out.exr");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("Blender add-on"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("view_frame"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out.exr"));
    fs::remove_all(dir);
}

// PNG and TIFF: exactly the sRGB encoding of the scene-linear result, RGB only (no depth as
// alpha); JPEG: RGB only, lossy; any other format refused before any work.
TEST(OutputFiles, DisplayFormatsAreDisplayReferredRgbOrRefused) {
    const fs::path dir = scratch("out_display");
    write_blender_render((dir / "in.exr").string(), 16, 12);
    ASSERT_EQ(apply(dir / "in.exr", dir / "linear.exr").status, 0);
    const OIIO::ImageBuf linear = read(dir / "linear.exr");
    // JPEG: lossy on this checkerboard, checked on the mean. Only PNG keeps wavecam's header.
    struct Case {
        const char* name;
        OIIO::TypeDesc format;
        bool exact, header;
        float tolerance;
    } cases[] = {{"out.png", OIIO::TypeDesc::UINT8, true, true, 0.6f / 255},
                 {"out.tif", OIIO::TypeDesc::UINT16, true, false, 1e-3f},
                 {"out.jpg", OIIO::TypeDesc::UINT8, false, false, 0.02f}};
    for (const Case& c : cases) {
        const auto r = apply(dir / "in.exr", dir / c.name);
        ASSERT_EQ(r.status, 0) << c.name << ": " << r.output;
        OIIO::ImageBuf shown((dir / c.name).string());
        ASSERT_TRUE(shown.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << c.name;
        EXPECT_EQ(shown.spec().nchannels, 3) << c.name;
        EXPECT_EQ(shown.nativespec().format, c.format) << c.name;
        if (c.header) {
            EXPECT_EQ(shown.spec().get_string_attribute("wavecam.view"), "Standard") << c.name;
        }
        double worst = 0, mean_error[3] = {0, 0, 0};
        for (int j = 0; j < 12; ++j)
            for (int i = 0; i < 16; ++i)
                for (int k = 0; k < 3; ++k) {
                    const double e = shown.getchannel(i, j, 0, k) - srgb_encode(linear.getchannel(i, j, 0, k));
                    worst = std::max(worst, std::fabs(e));
                    mean_error[k] += e / (16 * 12);
                }
        if (c.exact) {
            EXPECT_LT(worst, c.tolerance) << c.name;
        }
        for (double e : mean_error) EXPECT_LT(std::fabs(e), c.tolerance) << c.name;
    }
    for (const char* refused : {"out.hdr", "out.bmp", "out"}) {
        const auto r = apply(dir / "in.exr", dir / refused);
        EXPECT_NE(r.status, 0) << refused;
        EXPECT_NE(r.output.find("unsupported output format"), std::string::npos) << refused << ": " << r.output;
        EXPECT_FALSE(fs::exists(dir / refused)) << refused;
    }
    fs::remove_all(dir);
}

namespace {
// A PNG's colour chunks (PNG 1.2, 11.3.3): "gAMA" -> its gamma times 100000 (4 bytes, big-endian),
// "sRGB" -> its rendering intent (1 byte), read from the file itself.
std::map<std::string, unsigned> png_colour_chunks(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    const std::string d{std::istreambuf_iterator<char>(f), {}};
    std::map<std::string, unsigned> chunks;
    auto u32 = [&d](size_t at) {
        return unsigned((unsigned char)d[at]) << 24 | unsigned((unsigned char)d[at + 1]) << 16 |
               unsigned((unsigned char)d[at + 2]) << 8 | unsigned((unsigned char)d[at + 3]);
    };
    for (size_t at = 8; at + 8 <= d.size();) {  // after the signature: length, type, data, CRC
        const unsigned length = u32(at);
        const std::string type = d.substr(at + 4, 4);
        if (at + 12 + length > d.size()) break;
        if (type == "gAMA" && length == 4) chunks[type] = u32(at + 8);
        if (type == "sRGB" && length == 1) chunks[type] = (unsigned char)d[at + 8];
        at += 12 + length;
    }
    return chunks;
}
}  // namespace

// Display files say what they hold: sRGB-encoded pixels, tagged sRGB (a PNG's sRGB chunk and
// gAMA 1/2.2, not the gAMA 1.0 of linear data), with nothing left of the scene-linear input's
// colour description (ACES chromaticities and container flag, its linear space) in the header.
TEST(OutputFiles, DisplayFilesAreTaggedAsTheSrgbTheyHold) {
    const fs::path dir = scratch("out_display_tags");
    write_render((dir / "in.exr").string(), 12, 10, 3.0f, 35.0f);
    {
        OIIO::ImageBuf aces = read(dir / "in.exr");
        OIIO::ImageSpec& spec = aces.specmod();
        const float ap0[8] = {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.077f, 0.32168f, 0.33767f};
        spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), ap0);
        spec.attribute("acesImageContainerFlag", 1);
        spec.attribute("oiio:ColorSpace", "ACES2065-1");
        ASSERT_TRUE(aces.write((dir / "aces.exr").string()));
    }
    ASSERT_EQ(apply(dir / "aces.exr", dir / "out.png", "--png " + (dir / "also.png").string() + " --compare " +
                                                        (dir / "sheet.png").string()).status, 0);
    ASSERT_EQ(apply(dir / "aces.exr", dir / "out.jpg").status, 0);
    ASSERT_EQ(apply(dir / "aces.exr", dir / "out.tif").status, 0);
    ASSERT_EQ(run_command(kWavecam + " psf --pinhole 0.3mm --film-distance 65mm --source-distance inf --source-angle 0deg"
                                     " --wavelength 550nm --film-size 0.6mm --resolution 15 -o " + (dir / "psf.exr").string() +
                          " --png " + (dir / "psf.png").string()).status, 0);
    for (const char* name : {"out.png", "also.png", "sheet.png", "psf.png", "out.jpg", "out.tif"}) {
        OIIO::ImageBuf shown((dir / name).string());
        ASSERT_TRUE(shown.read()) << name << ": " << shown.geterror();
        const OIIO::ImageSpec& spec = shown.spec();
        EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"), "sRGB") << name;
        for (const char* stale : {"chromaticities", "acesImageContainerFlag", "oiio:Gamma", "wavecam.output-colorspace"})
            EXPECT_EQ(spec.find_attribute(stale), nullptr) << name << ": " << stale;
        if (OIIO::Filesystem::extension(name) == ".png") {
            const auto chunks = png_colour_chunks(dir / name);
            ASSERT_TRUE(chunks.count("gAMA")) << name;
            EXPECT_EQ(chunks.at("gAMA"), 45455u) << name << ": the gamma the file declares, times 100000";
            EXPECT_TRUE(chunks.count("sRGB")) << name;
        }
    }
    fs::remove_all(dir);
}

// Through the OIIO plugin (loaded into this process): wavecam.fov-from names where the fov came
// from, and the source's own string wavecam.fov is read as the file's attribute, not as a hint.
TEST(OutputFiles, PluginSaysWhereTheFieldOfViewCameFrom) {
    const fs::path dir = scratch("out_plugin_fov");
    OIIO::attribute("plugin_searchpath", std::string(WAVECAM_PLUGIN_DIR));
    write_render((dir / "plain.exr").string(), 8, 8, 2.0f, 0.0f);
    OIIO::ImageBuf tagged = read(dir / "plain.exr");
    tagged.specmod().attribute("wavecam.fov", "35deg");
    ASSERT_TRUE(tagged.write((dir / "tagged.exr").string()));
    const std::string plain = (dir / "plain.exr").string(), with_attr = (dir / "tagged.exr").string();
    struct Case {
        std::string name, from;
        float degrees;
    } cases[] = {{plain + ".wavecam?fov=40deg&wavelengths=3", "?fov= in the name", 40.0f},
                 {with_attr + ".wavecam?wavelengths=3", "the file's wavecam.fov attribute", 35.0f}};
    for (const Case& c : cases) {
        OIIO::ImageBuf out(c.name);
        ASSERT_TRUE(out.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << c.name << ": " << out.geterror();
        EXPECT_EQ(out.spec().get_string_attribute("wavecam.fov-from"), c.from) << c.name;
        EXPECT_FLOAT_EQ(out.spec().get_float_attribute("wavecam.fov"), c.degrees) << c.name;
    }
    fs::remove_all(dir);
}

namespace {
std::string bytes_of(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
}

// Every file in `dir` with its bytes (hidden temporaries included).
std::map<std::string, std::string> folder_bytes(const fs::path& dir) {
    std::map<std::string, std::string> all;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file() && !e.is_symlink()) all[e.path().string()] = bytes_of(e.path());
    return all;
}
}  // namespace

// No output may be an input or another output, however named (a symlink, a hard link, "./"),
// in every command (a mask the render's metadata names too): refused with exit 2 before any work, naming both paths, every file as it
// was, nothing new written. Output folders that do not exist or are files are refused too.
TEST(OutputFiles, NoOutputIsAnInputOrAnotherOutputInAnyCommand) {
    const fs::path dir = scratch("output_identity");
    const std::string d = dir.string() + "/";
    write_render(d + "in.exr", 8, 6, 2.0f, 30.0f);
    for (const char* frame : {"shot.0001.exr", "shot.0002.exr"}) write_render(d + frame, 8, 6, 2.0f, 30.0f);
    {  // a mask: a small grey image, also as the name a sweep would write
        OIIO::ImageBuf mask(OIIO::ImageSpec(16, 16, 1, OIIO::TypeDesc::FLOAT));
        OIIO::ImageBufAlgo::fill(mask, {1.0f});
        ASSERT_TRUE(mask.write(d + "mask.exr"));
        ASSERT_TRUE(mask.write(d + "m_psfs.png"));
    }
    {  // a render whose own metadata names the mask
        OIIO::ImageBuf tagged(d + "in.exr");
        ASSERT_TRUE(tagged.read(0, 0, true, OIIO::TypeDesc::FLOAT));
        tagged.specmod().attribute("wavecam.aperture", "mask:mask.exr");
        ASSERT_TRUE(tagged.write(d + "tagged.exr"));
    }
    fs::create_symlink(dir / "in.exr", dir / "link.exr");
    fs::create_hard_link(dir / "in.exr", dir / "hard.exr");
    // two shares of a tiny scene-sum job (2 wavelengths x 2 runs) for the merges
    const std::string job = " --method exact --film-distance 20mm --pinhole 0.05mm --wavelengths 2 --runs 2 "
                            "--film-subsamples 1 --seed 7";
    for (const char* k : {"1", "2"}) {
        auto r = run_command("cd " + d + " && " + kWavecam + " apply in.exr -o p" + k + ".exr" + job + " --share " +
                             k + "/2");
        ASSERT_EQ(r.status, 0) << r.output;
    }
    const std::string w = "cd " + d + " && " + kWavecam;
    const struct {
        std::string command, message;
    } rows[] = {
        {" apply in.exr -o o.exr --compare in.exr", "--compare in.exr is the same file as the render in.exr"},
        {" apply shot.#.exr -o out.#.exr --compare shot.#.exr --frames 1-2",
         "--compare (frame 1) shot.0001.exr is the same file as the render (frame 1) shot.0001.exr"},
        {" apply shot.#.exr -o shot.#.exr --frames 2", "-o (frame 2) shot.0002.exr is the same file as the render"},
        {" merge p1.exr p2.exr -o p1.exr", "-o p1.exr is the same file as the share file p1.exr"},
        {" merge 'p*.exr' -o ./p2.exr", "-o ./p2.exr is the same file as the share file"},
        {" merge p1.exr p2.exr -o in.exr", "-o in.exr is the same file as the shares' render"},
        {" merge p1.exr p2.exr -o m.exr --compare ./in.exr", "--compare ./in.exr is the same file as the shares' render"},
        {" merge p1.exr p2.exr -o m.exr --png m.exr", "--png m.exr is the same file as -o m.exr"},
        {" apply in.exr -o mask.exr --aperture mask:mask.exr", "-o mask.exr is the same file as the --aperture mask"},
        {" apply tagged.exr -o mask.exr", "-o mask.exr is the same file as tagged.exr's aperture mask mask.exr"},
        {" apply in.exr -o x.exr --compare x.exr", "--compare x.exr is the same file as -o x.exr"},
        {" apply in.exr -o x.exr --compare x.png --png ./x.png", "--png ./x.png is the same file as --compare x.png"},
        {" psf -o p.exr --png p.exr", "--png p.exr is the same file as -o p.exr"},
        {" psf -o mask.exr --aperture mask:./mask.exr", "-o mask.exr is the same file as the --aperture mask"},
        {" sweep -o m --aperture mask:m_psfs.png", "-o m_psfs.png is the same file as the --aperture mask"},
        {" apply in.exr -o link.exr", "-o link.exr is the same file as the render in.exr"},
        {" apply link.exr -o hard.exr", "-o hard.exr is the same file as the render link.exr"},
        {" apply in.exr -o " + d + "../" + dir.filename().string() + "/in.exr", "is the same file as the render"},
        {" farm submit in.exr -o hard.exr --tasks 2", "hard.exr is the same file as the render " + d + "in.exr"},
        {" apply in.exr -o nowhere/o.exr", "-o nowhere/o.exr: its folder nowhere cannot be used (No such file"},
        {" apply in.exr -o o.exr --png in.exr/o.png", "--png in.exr/o.png: in.exr is not a folder"},
        {" psf -o nowhere/p.exr", "-o nowhere/p.exr: its folder nowhere cannot be used"},
        {" merge p1.exr p2.exr -o nowhere/m.exr", "-o nowhere/m.exr: its folder nowhere cannot be used"},
        {" sweep -o nowhere/s", "-o nowhere/s.csv: its folder nowhere cannot be used"},
    };
    const auto before = folder_bytes(dir);
    for (const auto& row : rows) {
        const auto start = std::chrono::steady_clock::now();
        auto r = run_command(w + row.command);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        EXPECT_EQ(WEXITSTATUS(r.status), 2) << row.command << ":\n" << r.output;
        EXPECT_NE(r.output.find(row.message), std::string::npos) << row.command << ":\n" << r.output;
        EXPECT_EQ(r.output.find("wrote"), std::string::npos) << row.command << ":\n" << r.output;
        EXPECT_LT(seconds, 10) << row.command << ": refused before the work";
        EXPECT_EQ(folder_bytes(dir), before) << row.command << ": a file changed or appeared";
    }
    // the same files, named apart, are written
    auto ok = run_command(w + " apply in.exr -o o.exr --compare c.png --png o.png" + kQuick);
    EXPECT_EQ(ok.status, 0) << ok.output;
    auto merged = run_command(w + " merge p1.exr p2.exr -o m.exr");
    EXPECT_EQ(merged.status, 0) << merged.output;
    fs::remove_all(dir);
}
