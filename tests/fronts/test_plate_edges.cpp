// The plate kept whole at its edges and in its views (docs/compositing.md): light beyond the
// frame never invented, half output never inf, every view of a stereo file diffracted, a
// lens-shifted frame refused, no setting silently ignored, the depth channel recorded, alpha's
// range kept. Through `wavecam apply`, oiiotool and Python's OIIO, as a pipeline runs them.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <functional>
#include <map>
#include <vector>

#include "command_runner.h"

namespace fs = std::filesystem;
using namespace wavecam::test;

namespace {
const std::string kWavecam = WAVECAM_BINARY;
const std::string kPlugin = std::string("OIIO_LIBRARY_PATH=") + WAVECAM_PLUGIN_DIR + " ";
const std::string kQuick = " --film-distance 20mm --pinhole 0.2mm --wavelengths 3 ";

// A plate: channels `names`, each pixel's values from `value(channel, i, j)`, fov `fov_deg`,
// extra float or string attributes, every channel of type `type`.
struct Plate {
    int width = 16, height = 12;
    std::vector<std::string> names = {"R", "G", "B", "Z"};
    std::function<float(int c, int i, int j)> value = [](int c, int, int) { return c == 3 ? 3.0f : 0.5f; };
    float fov_deg = 40.0f;
    std::map<std::string, std::string> strings;
    OIIO::TypeDesc type = OIIO::TypeDesc::FLOAT;
    std::function<void(OIIO::ImageSpec&)> header;
};

void write(const fs::path& path, const Plate& p) {
    OIIO::ImageSpec spec(p.width, p.height, int(p.names.size()), p.type);
    spec.channelnames = p.names;
    spec.attribute("wavecam.fov", p.fov_deg);
    for (const auto& [k, v] : p.strings) spec.attribute(k, v);
    if (p.header) p.header(spec);
    std::vector<float> px(size_t(p.width) * p.height * p.names.size());
    for (int j = 0; j < p.height; ++j)
        for (int i = 0; i < p.width; ++i)
            for (size_t c = 0; c < p.names.size(); ++c)
                px[(size_t(j) * p.width + i) * p.names.size() + c] = p.value(int(c), i, j);
    auto out = OIIO::ImageOutput::create(path.string());
    ASSERT_TRUE(out && out->open(path.string(), spec)) << path;
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    out->close();
}

CommandRun apply(const fs::path& in, const fs::path& out, const std::string& extra = "") {
    return run_command(kWavecam + " apply " + in.string() + " -o " + out.string() + kQuick + extra);
}

// The sum of channels R, G and B over the image.
double light(const OIIO::ImageBuf& b) {
    double sum = 0;
    for (int c = 0; c < 3; ++c)
        for (int j = b.ybegin(); j < b.yend(); ++j)
            for (int i = b.xbegin(); i < b.xend(); ++i) sum += b.getchannel(i, j, 0, c);
    return sum;
}
}  // namespace

// A sun (1e6 in a wall of 1) on the frame's edge or in its corner, no overscan: its light comes
// back as when the render had a real margin of wall around it (within 5%), not copied into every
// point beyond the frame: through the default method, oiiotool, and the scene-sum methods. The
// same wall, a gradient and a texture keep their border: their edge is continued as before.
TEST(PlateEdges, LightBeyondTheFrameIsNeverInvented) {
    const fs::path dir = scratch("plate_edge_sun");
    using Scene = std::function<float(int c, int i, int j)>;  // radiance at frame pixel (i, j), any i, j
    // A frame of n x n pixels at `fov` degrees, diffracted alone or rendered with a real margin of
    // the same scene around it (the same pixel pitch) and cropped.
    struct Frame {
        int n, margin;
        double fov;
        std::string flags;
    };
    // 10 deg over 96 px at f = 50 mm, a 0.05 mm pinhole: an Airy ring ~10 px wide, kernels of tens of px
    const Frame frame{96, 48, 10.0, " --film-distance 50mm --pinhole 0.05mm --wavelengths 3 --no-vignetting "};
    auto run = [&](const Frame& f, const std::string& tag, const Scene& scene, bool real_margin) {
        Plate p;
        const int o = real_margin ? f.margin : 0;
        p.width = p.height = f.n + 2 * o;
        p.fov_deg = float(2 * std::atan(std::tan(f.fov / 2 * M_PI / 180) * (f.n + 2 * o) / f.n) * 180 / M_PI);
        p.value = [&scene, o](int c, int i, int j) { return c == 3 ? 10.0f : scene(c, i - o, j - o); };
        write(dir / (tag + ".exr"), p);
        auto r = run_command(kWavecam + " apply " + (dir / (tag + ".exr")).string() + " -o " +
                             (dir / (tag + "_out.exr")).string() + f.flags +
                             (real_margin ? " --overscan " + std::to_string(f.margin) : ""));
        EXPECT_EQ(r.status, 0) << r.output;
        return std::make_pair(read_float(dir / (tag + "_out.exr")), r.output);
    };
    const Scene wall = [](int, int, int) { return 1.0f; };
    const auto [wall_alone, wall_said] = run(frame, "wall", wall, false);
    const auto [wall_margin, unused] = run(frame, "wall_margin", wall, true);
    const int n = frame.n;
    for (const auto& [where, x, y] : {std::tuple<const char*, int, int>{"corner", 0, 0}, {"edge", n / 2, 0},
                                      {"far corner", n - 1, n - 1}}) {
        const Scene sun = [x = x, y = y](int, int i, int j) { return i == x && j == y ? 1e6f : 1.0f; };
        const auto [alone, said] = run(frame, "sun", sun, false);
        const auto [reference, unused2] = run(frame, "sun_margin", sun, true);
        const double kept = light(alone) - light(wall_alone), exact = light(reference) - light(wall_margin);
        std::printf("sun in the %s: its light %.4g alone, %.4g with a real margin: %.4f\n", where, kept, exact,
                    kept / exact);
        EXPECT_NEAR(kept / exact, 1.0, 0.05) << where << ": the sun's light " << kept << ", with a real margin "
                                             << exact;
        // the note names the overscan that would make it exact
        EXPECT_NE(said.find("--overscan"), std::string::npos) << where << said;
        EXPECT_NE(alone.spec().get_string_attribute("wavecam.edge"), "") << where;
        // oiiotool through the plugin: the same image, the same note on standard error
        const auto via = run_command(kPlugin + "oiiotool --iconfig wavecam:film-distance 50mm --iconfig wavecam:pinhole "
                                               "0.05mm --iconfig wavecam:wavelengths 3 --iconfig wavecam:vignetting false " +
                                     (dir / "sun.exr").string() + ".wavecam -o " + (dir / "sun_oiio.exr").string());
        ASSERT_EQ(via.status, 0) << via.output;
        EXPECT_NE(via.output.find("wavecam:overscan"), std::string::npos) << where << via.output;
        EXPECT_NEAR(light(read_float(dir / "sun_oiio.exr")) / light(alone), 1.0, 1e-5) << where;
    }
    EXPECT_EQ(wall_said.find("--overscan"), std::string::npos) << wall_said;
    // the scene-sum methods continue the edge the same way (a smaller frame: their sums cost more)
    const Frame small{24, 16, 10.0, " --film-distance 50mm --pinhole 0.1mm --wavelengths 3 --no-vignetting "
                                    "--method incoherent "};
    const Scene corner_sun = [](int, int i, int j) { return i == 0 && j == 0 ? 1e6f : 1.0f; };
    const double kept = light(run(small, "incoherent_sun", corner_sun, false).first) -
                        light(run(small, "incoherent_wall", wall, false).first);
    const double exact = light(run(small, "incoherent_sun_margin", corner_sun, true).first) -
                         light(run(small, "incoherent_wall_margin", wall, true).first);
    std::printf("incoherent method, sun in the corner: %.4g alone, %.4g with a real margin: %.4f\n", kept, exact,
                kept / exact);
    EXPECT_NEAR(kept / exact, 1.0, 0.05) << "the incoherent method";

    const Scene gradient = [](int c, int i, int j) { return 0.6f + 0.003f * float(i) + 0.001f * float(j) + 0.1f * c; };
    const Scene texture = [](int c, int i, int j) {
        const unsigned h = unsigned(i * 73856093) ^ unsigned(j * 19349663) ^ unsigned(c * 83492791);
        return 0.5f + 0.4f * float(h % 1000) / 1000.0f * (((i / 3 + j / 3) % 2) ? 1.0f : 0.3f);
    };
    for (const auto& [name, scene] : {std::pair<const char*, Scene>{"wall", wall}, {"gradient", gradient},
                                      {"texture", texture}}) {
        const auto [alone, said] = run(frame, std::string(name) + "_rim", scene, false);
        const auto [reference, unused3] = run(frame, std::string(name) + "_rim_margin", scene, true);
        double worst = 0, rim[2] = {0, 0};
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                if (i > 2 && j > 2 && i < n - 3 && j < n - 3) continue;  // the three outermost pixels
                for (int c = 0; c < 3; ++c) {
                    worst = std::max(worst, std::fabs(double(alone.getchannel(i, j, 0, c)) / reference.getchannel(i, j, 0, c) - 1));
                    rim[0] += alone.getchannel(i, j, 0, c);
                    rim[1] += reference.getchannel(i, j, 0, c);
                }
            }
        // a wall's border pixel by pixel within 1%; a gradient's within 2% (continued flat, where the
        // real margin goes on rising); a texture's beyond the frame is a guess either way (its own
        // pixels differ there): its rim's mean within 2%
        const std::string what = name;
        if (what == "texture") {
            EXPECT_NEAR(rim[0] / rim[1], 1.0, 0.02) << what << ": a rim at the frame's edge";
        } else {
            EXPECT_LT(worst, what == "wall" ? 0.01 : 0.02) << what << ": a rim at the frame's edge";
            EXPECT_EQ(said.find("--overscan"), std::string::npos) << name << said;
        }
    }
    fs::remove_all(dir);
}

// Values beyond half's range (a sun after diffraction) never reach the file as inf: written as
// float by default, clamped or refused as the half-overflow setting says, each time saying how
// many values and the largest.
TEST(PlateEdges, HalfOutputNeverOverflowsSilently) {
    const fs::path dir = scratch("plate_half");
    Plate p;
    p.value = [](int c, int i, int j) { return c == 3 ? 3.0f : (i == 8 && j == 6 ? 1e6f : 0.5f); };
    write(dir / "sun.exr", p);
    struct Case {
        std::string flags;
        int status;
        OIIO::TypeDesc written;
        std::string said;
    };
    for (const Case& k : {Case{"--pixel-type half", 0, OIIO::TypeDesc::FLOAT, "written as float"},
                          Case{"--pixel-type half --half-overflow clamp", 0, OIIO::TypeDesc::HALF, "clamped"},
                          Case{"--pixel-type half --half-overflow refuse", 1, OIIO::TypeDesc::UNKNOWN, "nothing written"}}) {
        const fs::path out = dir / "out.exr";
        fs::remove(out);
        const auto r = apply(dir / "sun.exr", out, k.flags);
        EXPECT_EQ(r.status != 0, k.status != 0) << k.flags << r.output;
        EXPECT_NE(r.output.find("values beyond half's range of 65504 (the largest "), std::string::npos)
            << k.flags << r.output;
        EXPECT_NE(r.output.find(k.said), std::string::npos) << k.flags << r.output;
        if (const size_t said = r.output.find("values beyond"); said != std::string::npos)
            std::printf("%s: %s", k.flags.c_str(), r.output.substr(r.output.rfind('\n', said) + 1).c_str());
        if (k.status != 0) {
            EXPECT_FALSE(fs::exists(out)) << k.flags;
            continue;
        }
        auto in = OIIO::ImageInput::open(out.string());
        ASSERT_TRUE(in) << k.flags;
        EXPECT_EQ(in->spec().channelformat(0), k.written) << k.flags;
        EXPECT_EQ(in->spec().channelformat(3), OIIO::TypeDesc::FLOAT) << "depth keeps its type";
        EXPECT_NE(in->spec().get_string_attribute("wavecam.half-overflow-written"), "") << k.flags;
        const OIIO::ImageBuf b = read_float(out);
        float most = 0;
        for (int j = 0; j < b.spec().height; ++j)
            for (int i = 0; i < b.spec().width; ++i)
                for (int c = 0; c < 3; ++c) {
                    ASSERT_TRUE(std::isfinite(b.getchannel(i, j, 0, c))) << k.flags;
                    most = std::max(most, b.getchannel(i, j, 0, c));
                }
        if (k.written == OIIO::TypeDesc::HALF) EXPECT_EQ(most, 65504.0f);
        else EXPECT_GT(most, 65504.0f);
    }
    // a half input kept half: a 65504 patch through XYZ overflows; by default it is written as float
    p.type = OIIO::TypeDesc::HALF;
    p.value = [](int c, int i, int j) { return c == 3 ? 3.0f : (i > 4 && i < 11 && j > 3 && j < 9 ? (c == 2 ? 65504.0f : 100.0f) : 0.5f); };
    write(dir / "patch.exr", p);
    const auto r = apply(dir / "patch.exr", dir / "patch_out.exr", "--output-colorspace CIE-XYZ-D65");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageBuf b = read_float(dir / "patch_out.exr");
    for (int j = 0; j < b.spec().height; ++j)
        for (int i = 0; i < b.spec().width; ++i)
            for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(b.getchannel(i, j, 0, c)));
    fs::remove_all(dir);
}

// A stereo file: every view diffracted with its own depth, as each view alone would be; the
// channels, their names and multiView kept. The default view unprefixed, or both prefixed
// (OpenEXR's and Blender's naming), through the command, oiiotool and Python.
TEST(PlateEdges, EveryViewOfAStereoFileIsDiffractedWithItsOwnDepth) {
    const fs::path dir = scratch("plate_stereo");
    auto scene = [](int view, int c, int i, int j) {  // the views differ in light and depth
        return ((i / 2 + j / 2 + view) % 2 ? 0.9f : 0.1f) * (1.0f + 0.2f * c) + 0.05f * view;
    };
    const float depth[2] = {3.0f, 0.05f};  // the right view's wall near: its PSF far wider
    for (int view = 0; view < 2; ++view) {
        Plate alone;
        alone.value = [&, view](int c, int i, int j) { return c == 3 ? depth[view] : scene(view, c, i, j); };
        write(dir / ("view" + std::to_string(view) + ".exr"), alone);
        ASSERT_EQ(apply(dir / ("view" + std::to_string(view) + ".exr"), dir / ("view" + std::to_string(view) + "_out.exr"))
                      .status,
                  0);
    }
    const OIIO::ImageBuf alone[2] = {read_float(dir / "view0_out.exr"), read_float(dir / "view1_out.exr")};
    struct Naming {
        std::string tag;
        std::vector<std::string> left, right;  // R, G, B, Z of each view
    };
    for (const Naming& k : {Naming{"default_unprefixed", {"R", "G", "B", "Z"}, {"right.R", "right.G", "right.B", "right.Z"}},
                            Naming{"both_prefixed", {"left.R", "left.G", "left.B", "left.Z"},
                                   {"right.R", "right.G", "right.B", "right.Z"}},
                            Naming{"blender", {"ViewLayer.Combined.left.R", "ViewLayer.Combined.left.G",
                                               "ViewLayer.Combined.left.B", "ViewLayer.Depth.left.Z"},
                                   {"ViewLayer.Combined.right.R", "ViewLayer.Combined.right.G",
                                    "ViewLayer.Combined.right.B", "ViewLayer.Depth.right.Z"}}}) {
        Plate stereo;
        stereo.names = k.left;
        stereo.names.insert(stereo.names.end(), k.right.begin(), k.right.end());
        stereo.value = [&](int c, int i, int j) {
            const int view = c / 4, ch = c % 4;
            return ch == 3 ? depth[view] : scene(view, ch, i, j);
        };
        stereo.header = [](OIIO::ImageSpec& s) {
            const OIIO::ustring views[2] = {OIIO::ustring("left"), OIIO::ustring("right")};
            s.attribute("multiView", OIIO::TypeDesc(OIIO::TypeDesc::STRING, 2), views);
        };
        const fs::path in = dir / (k.tag + ".exr");
        write(in, stereo);
        const std::vector<std::pair<std::string, std::string>> fronts = {
            {"command", kWavecam + " apply " + in.string() + " -o " + (dir / (k.tag + "_cmd.exr")).string() + kQuick},
            {"oiiotool", kPlugin + "oiiotool --iconfig wavecam:film-distance 20mm --iconfig wavecam:pinhole 0.2mm "
                                   "--iconfig wavecam:wavelengths 3 " + in.string() + ".wavecam -o " +
                             (dir / (k.tag + "_oiiotool.exr")).string()},
            {"python", kPlugin + "/usr/bin/python3 -c \"import OpenImageIO as oiio; c = oiio.ImageSpec(); "
                                 "c.attribute('wavecam:film-distance', '20mm'); c.attribute('wavecam:pinhole', '0.2mm'); "
                                 "c.attribute('wavecam:wavelengths', '3'); b = oiio.ImageBuf('" + in.string() +
                           ".wavecam', 0, 0, c); assert b.write('" + (dir / (k.tag + "_python.exr")).string() +
                           "'), b.geterror()\""}};
        for (const auto& [front, command] : fronts) {
            const auto r = run_command(command);
            ASSERT_EQ(r.status, 0) << k.tag << " " << front << ": " << r.output;
            const OIIO::ImageBuf out = read_float(dir / (k.tag + "_" + (front == "command" ? "cmd" : front) + ".exr"));
            EXPECT_EQ(out.spec().nchannels, 8) << k.tag << " " << front;
            const OIIO::ParamValue* mv = out.spec().find_attribute("multiView");
            ASSERT_NE(mv, nullptr) << k.tag << " " << front << ": multiView kept";
            for (int view = 0; view < 2; ++view) {
                const std::vector<std::string>& names = view == 0 ? k.left : k.right;
                double worst = 0, change = 0;
                for (int ch = 0; ch < 3; ++ch) {
                    const int c = out.spec().channelindex(names[ch]);
                    ASSERT_GE(c, 0) << names[ch];
                    for (int j = 0; j < 12; ++j)
                        for (int i = 0; i < 16; ++i) {
                            const float got = out.getchannel(i, j, 0, c), want = alone[view].getchannel(i, j, 0, ch);
                            worst = std::max(worst, double(std::fabs(got - want)));
                            change = std::max(change, double(std::fabs(got - scene(view, ch, i, j))));
                        }
                }
                EXPECT_LT(worst, 1e-5) << k.tag << " " << front << ": view " << view << " as that view alone";
                EXPECT_GT(change, 0.01) << k.tag << " " << front << ": view " << view << " was diffracted";
                const int z = out.spec().channelindex(names[3]);
                ASSERT_GE(z, 0);
                EXPECT_EQ(out.getchannel(3, 3, 0, z), depth[view]) << "depth passes through";
            }
            EXPECT_NE(out.spec().get_string_attribute("wavecam.views"), "") << k.tag << " " << front;
        }
    }
    fs::remove_all(dir);
}

// A lens-shifted render (screenWindowCenter off (0, 0)) has its optical axis off the frame's
// centre, which wavecam's camera cannot hold: refused by name through the command and the
// plugin, never diffracted about the wrong centre. A zoomed screen window without an fov given:
// refused the same way.
TEST(PlateEdges, ALensShiftedFrameIsRefusedByName) {
    const fs::path dir = scratch("plate_shift");
    Plate shifted;
    shifted.header = [](OIIO::ImageSpec& s) {
        const float centre[2] = {0.2f, 0.0f};
        s.attribute("screenWindowCenter", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, OIIO::TypeDesc::VEC2), centre);
    };
    write(dir / "shifted.exr", shifted);
    Plate zoomed;
    zoomed.header = [](OIIO::ImageSpec& s) { s.attribute("screenWindowWidth", 2.0f); };
    write(dir / "zoomed.exr", zoomed);
    for (const auto& [file, word] : {std::pair<std::string, std::string>{"shifted", "screenWindowCenter is (0.2, 0)"},
                                     {"zoomed", "screenWindowWidth is 2"}}) {
        auto r = apply(dir / (file + ".exr"), dir / "out.exr");
        EXPECT_NE(r.status, 0) << file;
        EXPECT_NE(r.output.find(word), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(dir / "out.exr"));
        r = run_command(kPlugin + "oiiotool --iconfig wavecam:film-distance 20mm " + (dir / (file + ".exr")).string() +
                        ".wavecam -o " + (dir / "out.exr").string());
        EXPECT_NE(r.status, 0) << file;
        EXPECT_NE(r.output.find(word), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(dir / "out.exr"));
        r = run_command(kPlugin + "/usr/bin/python3 -c \"import OpenImageIO as oiio; b = oiio.ImageBuf('" +
                        (dir / (file + ".exr")).string() + ".wavecam'); print(b.read(), b.geterror())\"");
        EXPECT_NE(r.output.find("False"), std::string::npos) << file << ": " << r.output;
        EXPECT_NE(r.output.find(word), std::string::npos) << r.output;
    }
    // the fov given describes the zoomed frame: taken
    EXPECT_EQ(apply(dir / "zoomed.exr", dir / "out.exr", "--fov 40deg").status, 0);
    fs::remove_all(dir);
}

// A mistyped wavecam key never falls back to the default: refused on every route, naming the
// nearest known key.
TEST(PlateEdges, NoSettingIsSilentlyIgnored) {
    const fs::path dir = scratch("plate_typos");
    write(dir / "shot.exr", Plate{});
    Plate typo;
    typo.strings = {{"wavecam.pinhol", "0.02mm"}};
    write(dir / "pinhol.exr", typo);
    typo.strings = {{"wavecam.film_distance", "30mm"}};
    write(dir / "film_distance.exr", typo);
    const std::string shot = (dir / "shot.exr").string(), out = (dir / "out.exr").string();
    struct Case {
        std::string route, command, said;
    };
    const std::vector<Case> cases = {
        {"--iconfig with a dot", kPlugin + "oiiotool --iconfig wavecam.pinhole 0.02mm " + shot + ".wavecam -o " + out,
         "--iconfig wavecam:pinhole 0.02mm"},
        {"--iconfig misspelt", kPlugin + "oiiotool --iconfig wavecam:pinhol 0.02mm " + shot + ".wavecam -o " + out,
         "did you mean 'pinhole'"},
        {"?key= misspelt", kPlugin + "oiiotool '" + shot + ".wavecam?pinhol=0.02mm' -o " + out, "did you mean 'pinhole'"},
        {"python hint with a dot",
         kPlugin + "/usr/bin/python3 -c \"import OpenImageIO as oiio; c = oiio.ImageSpec(); c.attribute('wavecam.pinhole', "
                   "'0.02mm'); b = oiio.ImageBuf('" + shot + ".wavecam', 0, 0, c); b.read(); print(b.geterror())\"",
         "wavecam:pinhole"},
        {"header attribute (command)", kWavecam + " apply " + (dir / "pinhol.exr").string() + " -o " + out + kQuick,
         "wavecam.pinhol"},
        {"header attribute (plugin)",
         kPlugin + "oiiotool " + (dir / "film_distance.exr").string() + ".wavecam -o " + out,
         "did you mean 'film-distance'"},
    };
    for (const Case& k : cases) {
        fs::remove(out);
        const auto r = run_command(k.command);
        if (k.route.rfind("python", 0) != 0) {
            EXPECT_NE(r.status, 0) << k.route << ": " << r.output;
        }
        EXPECT_NE(r.output.find(k.said), std::string::npos) << k.route << ": " << r.output;
        EXPECT_FALSE(fs::exists(out)) << k.route;
    }
    fs::remove_all(dir);
}

// The depth channel used is recorded, and a later run of the output reads the same one.
TEST(PlateEdges, TheDepthChannelUsedIsRecorded) {
    const fs::path dir = scratch("plate_depth_channel");
    Plate p;
    p.names = {"R", "G", "B", "Z", "depth.Z"};
    p.value = [](int c, int i, int) { return c == 3 ? 0.01f : c == 4 ? 3.0f : 0.2f + 0.05f * float(i % 3); };
    write(dir / "in.exr", p);
    auto r = apply(dir / "in.exr", dir / "once.exr", "--depth-channel depth.Z");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(read_float(dir / "once.exr").spec().get_string_attribute("wavecam.depth-channel"), "depth.Z");
    // read again (Z there is 1 cm: a run that took it would be refused as too near the pinhole)
    r = apply(dir / "once.exr", dir / "twice.exr", "--diffract-again");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(read_float(dir / "twice.exr").spec().get_string_attribute("wavecam.depth-channel"), "depth.Z");
    // the plugin records it the same way
    r = run_command(kPlugin + "oiiotool --iconfig wavecam:film-distance 20mm --iconfig wavecam:pinhole 0.2mm "
                              "--iconfig wavecam:wavelengths 3 --iconfig wavecam:depth-channel depth.Z " +
                    (dir / "in.exr").string() + ".wavecam -o " + (dir / "plugin.exr").string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(read_float(dir / "plugin.exr").spec().get_string_attribute("wavecam.depth-channel"), "depth.Z");
    fs::remove_all(dir);
}

// Alpha is coverage: a negative one is refused like negative light (or clamped, and counted,
// by the same setting); one above 1 is kept above 1.
TEST(PlateEdges, AlphaOutOfRangeIsRefusedOrKept) {
    const fs::path dir = scratch("plate_alpha");
    Plate p;
    p.names = {"R", "G", "B", "A", "Z"};
    p.value = [](int c, int i, int j) {
        if (c == 4) return 3.0f;
        const float a = i == 3 && j == 4 ? -0.5f : (i < 8 ? 1.0f : 0.0f);
        return c == 3 ? a : 0.5f * std::max(a, 0.0f);
    };
    write(dir / "negative.exr", p);
    auto r = apply(dir / "negative.exr", dir / "out.exr");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("channel 'A' at pixel (3, 4) is -0.5"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out.exr"));
    r = run_command(kPlugin + "oiiotool --iconfig wavecam:film-distance 20mm " + (dir / "negative.exr").string() +
                    ".wavecam -o " + (dir / "out.exr").string());
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("channel 'A' at pixel (3, 4) is -0.5"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "out.exr"));
    r = apply(dir / "negative.exr", dir / "out.exr", "--negative clamp");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(read_float(dir / "out.exr").spec().get_string_attribute("wavecam.negative-clamped"), "1 values");

    p.value = [](int c, int i, int) {
        if (c == 4) return 3.0f;
        const float a = i < 8 ? 1.5f : 0.0f;  // an additive element's coverage
        return c == 3 ? a : 0.5f * a;
    };
    write(dir / "above.exr", p);
    r = apply(dir / "above.exr", dir / "above_out.exr");
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageBuf out = read_float(dir / "above_out.exr");
    EXPECT_NEAR(out.getchannel(1, 6, 0, 3), 1.5f, 1e-3) << "alpha above 1 kept";
    fs::remove_all(dir);
}
