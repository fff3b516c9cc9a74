// The OpenImageIO plugin through the real oiiotool and the Python bindings, as users run it.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>

#include <cmath>
#include <fstream>

#include "command_runner.h"

namespace fs = std::filesystem;
using namespace wavecam::test;

namespace {
const std::string kEnv = std::string("OIIO_LIBRARY_PATH=") + WAVECAM_PLUGIN_DIR + " ";
const std::string kHints =
    " --iconfig wavecam:film-distance 20mm --iconfig wavecam:pinhole 0.2mm --iconfig wavecam:wavelengths 3"
    " --iconfig wavecam:runs 1 --iconfig wavecam:seed 7 ";

std::vector<float> pixels(const fs::path& p) {
    OIIO::ImageBuf b(p.string());
    b.read(0, 0, true, OIIO::TypeDesc::FLOAT);
    std::vector<float> v(size_t(b.spec().image_pixels()) * b.spec().nchannels);
    b.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, v.data());
    return v;
}
}  // namespace

// The exact method is bit for bit. The fast method agrees to float rounding only: inside an
// OIIO host it differs from the command line in the 7th significant digit (the host process's
// floating-point environment differs; the exact cause is not pinned down).
TEST(Plugin, OiiotoolMatchesWavecamApply) {
    const fs::path dir = scratch("plugin_same");
    write_render((dir / "shot.exr").string(), 10, 8, 3.0f, 35.0f);
    for (const std::string method : {"exact", "fast"}) {
        const auto a = run_command(kEnv + "oiiotool" + kHints + "--iconfig wavecam:method " + method + " " +
                                   (dir / "shot.exr.wavecam").string() + " -o " + (dir / "via_oiio.exr").string());
        ASSERT_EQ(a.status, 0) << a.output;
        const auto b = run_command(std::string(WAVECAM_BINARY) + " apply " + (dir / "shot.exr").string() + " -o " +
                                   (dir / "via_cli.exr").string() +
                                   " --film-distance 20mm --pinhole 0.2mm --wavelengths 3 --runs 1 --seed 7 --method " +
                                   method);
        ASSERT_EQ(b.status, 0) << b.output;
        const auto pa = pixels(dir / "via_oiio.exr"), pb = pixels(dir / "via_cli.exr");
        ASSERT_EQ(pa.size(), pb.size());
        if (method == "exact") {
            EXPECT_EQ(pa, pb);
        } else {
            for (size_t k = 0; k < pa.size(); ++k) ASSERT_NEAR(pa[k], pb[k], 1e-5 * (1 + std::fabs(pb[k]))) << k;
        }
    }
    fs::remove_all(dir);
}

TEST(Plugin, DescriptionFileRuns) {
    const fs::path dir = scratch("plugin_desc");
    fs::create_directories(dir / "renders");
    write_render((dir / "renders" / "shot.exr").string(), 8, 8, 3.0f, 35.0f);
    {
        OIIO::ImageBuf mask(OIIO::ImageSpec(4, 4, 1, OIIO::TypeDesc::UINT8));
        const float open[1] = {1.0f};
        for (int j = 1; j < 3; ++j)
            for (int i = 1; i < 3; ++i) mask.setpixel(i, j, open);
        ASSERT_TRUE(mask.write((dir / "renders" / "pinhole.png").string()));
    }
    // the mask, like the source, is found beside the description
    std::ofstream(dir / "shot.wavecam") << "source = \"renders/shot.exr\"\npinhole = \"0.2mm\"\n"
                                           "film-distance = \"20mm\"\nwavelengths = [\"450nm\", \"550nm\", \"650nm\"]\n"
                                           "runs = 1\noutput-colorspace = \"ACEScg\"\naperture = \"mask:renders/pinhole.png\"\n";
    const auto r = run_command(kEnv + "oiiotool " + (dir / "shot.wavecam").string() + " -o " + (dir / "o.exr").string());
    ASSERT_EQ(r.status, 0) << r.output;
    OIIO::ImageBuf out((dir / "o.exr").string());
    ASSERT_TRUE(out.read());
    EXPECT_EQ(out.spec().get_string_attribute("wavecam.output-colorspace"), "ACEScg");
    EXPECT_EQ(out.spec().get_string_attribute("wavecam.wavelengths"), "450nm,550nm,650nm");
    const std::string aperture = out.spec().get_string_attribute("wavecam.aperture");
    EXPECT_EQ(aperture.rfind("mask:", 0), 0u) << aperture;
    EXPECT_NE(aperture.find("pinhole.png"), std::string::npos) << aperture;
    fs::remove_all(dir);
}

TEST(Plugin, BadDescriptionsFailWithThePluginsMessage) {
    const fs::path dir = scratch("plugin_bad");
    fs::create_directories(dir / "inner");
    write_render((dir / "shot.exr").string(), 8, 8, 3.0f, 35.0f);
    struct Case {
        std::string text, expect;
    } cases[] = {
        {"source = \"missing.exr\"\n", "does not exist"},
        {"source = \"../shot.exr\"\n", "escapes the description's folder"},
        {"source = \"/etc/passwd\"\n", "escapes the description's folder"},
        {"source = \"shot.exr\"\npinhole = \"0.2\"\n", "pinhole: expected a length"},
        {"source = \"shot.exr\"\nfocus = \"2m\"\n", "focus: unknown key"},
        {"source = \"shot.exr\"\naperture = \"mask:../mask.png\"\n", "aperture: mask '../mask.png' escapes"},
        {"source = \"shot.exr\"\naperture = \"polygon:2\"\n", "aperture: expected the number of sides"},
        {"pinhole = \"0.2mm\"\n", "source: missing"},
        {"source = [ unclosed\n", "not a wavecam description"},
        {"\x01\x02\xff binary", "not a wavecam description"},
    };
    int k = 0;
    for (const Case& c : cases) {
        // descriptions live in inner/ except the one that reaches up and out of it
        const fs::path desc = dir / "inner" / ("case" + std::to_string(k++) + ".wavecam");
        std::string text = c.text;
        if (text.find("shot.exr\"\n") != std::string::npos && text.find("..") == std::string::npos) {
            fs::copy_file(dir / "shot.exr", dir / "inner" / "shot.exr", fs::copy_options::overwrite_existing);
        }
        std::ofstream(desc) << text;
        const auto r = run_command(kEnv + "oiiotool " + desc.string() + " -o " + (dir / "o.exr").string());
        EXPECT_NE(r.status, 0) << c.text;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.text << ": " << r.output;
        EXPECT_NE(r.output.find(desc.filename().string()), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(dir / "o.exr"));
    }
    fs::remove_all(dir);
}

TEST(Plugin, PythonBindingsOpenADiffractedImage) {
    const fs::path dir = scratch("plugin_py");
    write_render((dir / "shot.exr").string(), 8, 6, 3.0f, 35.0f);
    const std::string script =
        "import OpenImageIO as oiio; b = oiio.ImageBuf('" + (dir / "shot.exr.wavecam").string() +
        "?wavelengths=3&runs=1&pinhole=0.2mm&film-distance=20mm'); "
        "print(b.spec().width, b.spec().height, b.spec().channelnames, b.getpixel(4, 3)[3])";
    const auto r = run_command(kEnv + "/usr/bin/python3 -c \"" + script + "\"");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("8 6 ('R', 'G', 'B', 'Z') 3.0"), std::string::npos) << r.output;
    fs::remove_all(dir);
}

TEST(Plugin, FrameSequencesThroughOiiotool) {
    const fs::path dir = scratch("plugin_frames");
    for (int f = 1; f <= 3; ++f) write_render((dir / ("shot.000" + std::to_string(f) + ".exr")).string(), 6, 6, 3.0f, 35.0f);
    const auto r = run_command(kEnv + "oiiotool --frames 1-3" + kHints + (dir / "shot.#.exr.wavecam").string() +
                               " -o " + (dir / "out.#.exr").string());
    ASSERT_EQ(r.status, 0) << r.output;
    for (int f = 1; f <= 3; ++f) EXPECT_TRUE(fs::exists(dir / ("out.000" + std::to_string(f) + ".exr")));
    fs::remove_all(dir);
}
