// The OpenImageIO plugin through the real oiiotool and the Python bindings, as users run it.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

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

// The random-phase method's direct sums are bit for bit. The convolution method, and the
// random-phase method's nufft summation (libm and FFTs, as the convolution method), agree to
// float rounding only: inside an OIIO host
// they differ from the command line in the 7th significant digit (the host process's
// floating-point environment differs; the exact cause is not pinned down).
TEST(Plugin, OiiotoolMatchesWavecamApply) {
    const fs::path dir = scratch("plugin_same");
    write_render((dir / "shot.exr").string(), 10, 8, 3.0f, 35.0f);
    for (const std::string how : {"random-phase direct", "random-phase nufft", "convolution auto"}) {
        const std::string method = how.substr(0, how.find(' ')), summation = how.substr(how.find(' ') + 1);
        const auto a = run_command(kEnv + "oiiotool" + kHints + "--iconfig wavecam:method " + method +
                                   " --iconfig wavecam:summation " + summation + " " +
                                   (dir / "shot.exr.wavecam").string() + " -o " + (dir / "via_oiio.exr").string());
        ASSERT_EQ(a.status, 0) << a.output;
        const auto b = run_command(std::string(WAVECAM_BINARY) + " apply " + (dir / "shot.exr").string() + " -o " +
                                   (dir / "via_cli.exr").string() +
                                   " --film-distance 20mm --pinhole 0.2mm --wavelengths 3 --runs 1 --seed 7 --method " +
                                   method + " --summation " + summation);
        ASSERT_EQ(b.status, 0) << b.output;
        if (method != "convolution") {
            // one estimate in the plugin's log and the command's: the job and its terms (the time
            // is each run's own measured rate)
            auto job = [](const std::string& out, const std::string& label) {
                const size_t end = out.find(" terms, about ");
                if (end == std::string::npos) return std::string();
                const size_t newline = out.rfind('\n', end), start = newline == std::string::npos ? 0 : newline + 1;
                const std::string line = out.substr(start, end - start);
                return line.rfind(label + ": ", 0) == 0 ? line.substr(label.size() + 2) : "(no label) " + line;
            };
            const std::string via_oiio = job(a.output, "wavecam: estimate"), via_cli = job(b.output, "apply");
            EXPECT_NE(via_oiio.find(" = "), std::string::npos) << a.output;
            EXPECT_EQ(via_oiio, via_cli);
        }
        const auto pa = pixels(dir / "via_oiio.exr"), pb = pixels(dir / "via_cli.exr");
        ASSERT_EQ(pa.size(), pb.size());
        if (how == "random-phase direct") {
            EXPECT_EQ(pa, pb);
        } else {
            for (size_t k = 0; k < pa.size(); ++k) ASSERT_NEAR(pa[k], pb[k], 1e-5 * (1 + std::fabs(pb[k]))) << how << k;
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

// Every failure reaches the user with the plugin's own message, through oiiotool and Python,
// with and without hints. oiiotool without --iconfig reports only "File does not exist" for
// a name not on disk, so the plugin also writes its message to stderr there (and only there).
namespace {
struct FailingInput {
    std::string what;
    std::string name;     // relative to the scratch folder; may carry ?key=value
    std::string hint_key;  // the same failure through a hint: --iconfig wavecam:KEY VALUE
    std::string hint_value;
    std::string hinted_name;
    std::string expect;
    std::string hinted_expect;  // where the hint words it otherwise
};

std::vector<FailingInput> failing_inputs(const fs::path& dir) {
    write_render((dir / "nofov.exr").string(), 6, 6, 3.0f, 0.0f);
    write_render((dir / "shot.exr").string(), 6, 6, 3.0f, 35.0f);
    OIIO::ImageBuf tagged((dir / "shot.exr").string());
    tagged.read(0, 0, true, OIIO::TypeDesc::FLOAT);
    tagged.specmod().attribute("wavecam.pinhole", "0.2");  // a bad unit in the source's own metadata
    tagged.write((dir / "tagged.exr").string());
    ::mkfifo((dir / "fifo.exr").c_str(), 0600);
    return {
        // the plugin's words for a setting: a hint or ?KEY= in the name, never a command-line flag
        {"missing fov", "nofov.exr.wavecam", "wavelengths", "3", "nofov.exr.wavecam",
         "give it with --iconfig wavecam:fov 50deg or ?fov=50deg in the name", ""},
        {"bad unit in the name", "shot.exr.wavecam?pinhole=0.2", "pinhole", "0.2", "shot.exr.wavecam",
         "shot.exr: ?pinhole= in the name: expected a length", "shot.exr: --iconfig wavecam:pinhole: expected a length"},
        {"bad unit in the source's metadata", "tagged.exr.wavecam", "wavelengths", "3", "tagged.exr.wavecam",
         "tagged.exr: wavecam.pinhole: expected a length", ""},
        {"missing source", "missing.exr.wavecam", "wavelengths", "3", "missing.exr.wavecam",
         "missing.exr: no such file", ""},
        // refused by range before any work (it aborted on memory), and a source that
        // is no file (a FIFO blocked the read)
        {"a pinhole wider than the film", "shot.exr.wavecam?pinhole=1000m", "pinhole", "1000m", "shot.exr.wavecam",
         "shot.exr: a pinhole of 1e+06mm is wider than the film (", ""},
        {"a FIFO as the source", "fifo.exr.wavecam", "wavelengths", "3", "fifo.exr.wavecam",
         "fifo.exr: cannot be read as an image (a named pipe (FIFO); expected an image file)", ""},
        // the name's own items: as the command refuses an option given twice; percent escapes
        {"a setting given twice in the name", "shot.exr.wavecam?pinhole=0.2mm&pinhole=0.3mm", "wavelengths", "3",
         "shot.exr.wavecam?pinhole=0.2mm&pinhole=0.3mm", "?pinhole= given twice; give each setting once", ""},
        {"a bad percent escape", "shot.exr.wavecam?pinhole=0.2%zzmm", "wavelengths", "3",
         "shot.exr.wavecam?pinhole=0.2%zzmm",
         "'%zz' in 'pinhole=0.2%zzmm' is not a percent escape; expected % and two hex digits", ""},
        {"an item without a setting name", "shot.exr.wavecam?=0.2mm", "wavelengths", "3", "shot.exr.wavecam?=0.2mm",
         "'=0.2mm' has no setting name; expected KEY=VALUE items joined by &, e.g. ?pinhole=0.2mm&runs=8", ""},
    };
}
}  // namespace

TEST(Plugin, EveryFailureReachesOiiotoolWithThePluginsMessage) {
    const fs::path dir = scratch("plugin_errors_oiiotool");
    for (const FailingInput& c : failing_inputs(dir)) {
        for (const bool hinted : {false, true}) {
            const std::string name = (dir / (hinted ? c.hinted_name : c.name)).string();
            const std::string hints = hinted ? " --iconfig wavecam:" + c.hint_key + " " + c.hint_value + " " : " ";
            const auto r = run_command(kEnv + "oiiotool" + hints + "'" + name + "' -o " + (dir / "o.exr").string());
            const std::string& expect = hinted && !c.hinted_expect.empty() ? c.hinted_expect : c.expect;
            EXPECT_NE(r.status, 0) << c.what;
            EXPECT_NE(r.output.find(expect), std::string::npos) << c.what << (hinted ? " (hinted)" : "") << ": " << r.output;
            EXPECT_EQ(r.output.find("--fov"), std::string::npos) << r.output;
            EXPECT_FALSE(fs::exists(dir / "o.exr")) << c.what;
            // said once: oiiotool's own line, or ours where oiiotool drops it, never both
            const size_t first = r.output.find(expect);
            EXPECT_EQ(r.output.find(expect, first + 1), std::string::npos) << r.output;
        }
    }
    fs::remove_all(dir);
}

TEST(Plugin, EveryFailureReachesPythonWithThePluginsMessage) {
    const fs::path dir = scratch("plugin_errors_py");
    const auto cases = failing_inputs(dir);
    // One line per (case, way of opening): ImageBuf and ImageInput.open, plain and with a hint.
    std::ofstream script(dir / "open_all.py");
    script << "import sys, OpenImageIO as oiio\n"
              "def report(label, ok, err):\n"
              "    print(label, 'OPENED' if ok else 'FAILED', err.replace(chr(10), ' '))\n"
              "for name, key, value, hinted_name in zip(*[iter(sys.argv[1:])] * 4):\n"
              "    b = oiio.ImageBuf(name)\n"
              "    report(name + ' ImageBuf', b.read(0, 0, True, 'float'), b.geterror())\n"
              "    i = oiio.ImageInput.open(name)\n"
              "    report(name + ' ImageInput', i is not None, oiio.geterror())\n"
              "    config = oiio.ImageSpec()\n"
              "    config.attribute('wavecam:' + key, value)\n"
              "    b = oiio.ImageBuf(hinted_name, 0, 0, config)\n"
              "    report(hinted_name + ' hinted ImageBuf', b.read(0, 0, True, 'float'), b.geterror())\n"
              "    i = oiio.ImageInput.open(hinted_name, config)\n"
              "    report(hinted_name + ' hinted ImageInput', i is not None, oiio.geterror())\n";
    script.close();
    std::string args;
    for (const FailingInput& c : cases)
        args += " '" + (dir / c.name).string() + "' " + c.hint_key + " " + c.hint_value + " '" +
                (dir / c.hinted_name).string() + "'";
    const auto r = run_command(kEnv + "/usr/bin/python3 " + (dir / "open_all.py").string() + args);
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find("OPENED"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("wavecam ERROR"), std::string::npos) << "stderr is for oiiotool only: " << r.output;
    std::istringstream lines(r.output);
    std::string line;
    size_t k = 0;
    while (std::getline(lines, line)) {
        ASSERT_LT(k / 4, cases.size()) << r.output;
        EXPECT_NE(line.find(" FAILED "), std::string::npos) << line;
        const FailingInput& c = cases[k / 4];
        const bool hinted = k % 4 >= 2;
        const std::string& expect = hinted && !c.hinted_expect.empty() ? c.hinted_expect : c.expect;
        EXPECT_NE(line.find(expect), std::string::npos) << c.what << ": " << line;
        ++k;
    }
    EXPECT_EQ(k, 4 * cases.size()) << r.output;
    fs::remove_all(dir);
}

// A name's items are percent-decoded (a mask whose file name has a space). An item without '='
// (a trailing '&') is refused by OpenImageIO itself before any reader sees the name
// (ImageInput::create, "malformed filename"); a host that hands the name to the plugin's reader
// directly gets the plugin's words.
TEST(Plugin, NameItemsArePercentDecodedAndEmptyItemsWorded) {
    const fs::path dir = scratch("plugin_query");
    write_render((dir / "shot.exr").string(), 8, 8, 3.0f, 35.0f);
    {
        OIIO::ImageBuf mask(OIIO::ImageSpec(4, 4, 1, OIIO::TypeDesc::UINT8));
        const float open[1] = {1.0f};
        for (int j = 1; j < 3; ++j)
            for (int i = 1; i < 3; ++i) mask.setpixel(i, j, open);
        ASSERT_TRUE(mask.write((dir / "my mask.png").string()));
    }
    const std::string name = (dir / "shot.exr.wavecam").string() + "?aperture=mask:" + (dir / "my%20mask.png").string() +
                             "&pinhole=0.2mm&film-distance=20mm&wavelen%67ths=3";
    auto r = run_command(kEnv + "oiiotool '" + name + "' -o " + (dir / "o.exr").string());
    ASSERT_EQ(r.status, 0) << r.output;
    OIIO::ImageBuf out((dir / "o.exr").string());
    ASSERT_TRUE(out.read());
    EXPECT_NE(out.spec().get_string_attribute("wavecam.aperture").find("my mask.png"), std::string::npos)
        << out.spec().get_string_attribute("wavecam.aperture");
    EXPECT_EQ(out.spec().get_string_attribute("wavecam.wavelengths"), "450nm,550nm,650nm");
    // the reader itself, loaded into this process
    OIIO::attribute("plugin_searchpath", std::string(WAVECAM_PLUGIN_DIR));
    auto reader = OIIO::ImageInput::create("wavecam");
    ASSERT_TRUE(reader) << OIIO::geterror();
    OIIO::ImageSpec spec;
    EXPECT_FALSE(reader->open((dir / "shot.exr.wavecam").string() + "?pinhole=0.2mm&", spec));
    const std::string error = reader->geterror();
    EXPECT_NE(error.find("shot.exr.wavecam?pinhole=0.2mm&: an empty item after '?' or '&' (a trailing or doubled "
                         "'&'); expected KEY=VALUE items joined by &"),
              std::string::npos)
        << error;
    fs::remove_all(dir);
}

// A result is kept for its source file as it is: the same relative name in another working
// folder is that folder's render, and a render written again (renamed over the old one, as
// renderers and wavecam write; or rewritten at another size) is read again, in one process.
// The outputs are checked against each other: the diffraction is linear in the radiance.
TEST(Plugin, AResultFollowsItsSourceFileNotItsName) {
    const fs::path dir = scratch("plugin_result_source");
    fs::create_directories(dir / "a");
    fs::create_directories(dir / "b");
    std::ofstream(dir / "follow.py") << R"(import os, sys, OpenImageIO as oiio
def render(path, value, width=8):
    s = oiio.ImageSpec(width, 6, 4, 'float'); s.channelnames = ('R', 'G', 'B', 'Z'); s.attribute('wavecam.fov', 35.0)
    b = oiio.ImageBuf(s); oiio.ImageBufAlgo.fill(b, (value, value, value, 3.0)); assert b.write(path)
def centre(name):
    i = oiio.ImageInput.open(name)
    assert i, oiio.geterror()
    p = i.read_image('float'); w = i.spec().width; i.close()
    return w, float(p[3, w // 2, 1])
q = 'shot.exr.wavecam?pinhole=0.2mm&film-distance=20mm&wavelengths=3'
render('a/shot.exr', 1.0); render('b/shot.exr', 2.0)
os.chdir('a'); print('a', *centre(q))
os.chdir('../b'); print('b', *centre(q))
render('shot.new.exr', 4.0); os.replace('shot.new.exr', 'shot.exr'); print('renamed', *centre(q))
render('shot.exr', 4.0, width=10); print('resized', *centre(q))
)";
    const auto r = run_command("cd " + dir.string() + " && " + kEnv + "/usr/bin/python3 follow.py");
    ASSERT_EQ(r.status, 0) << r.output;
    std::istringstream lines(r.output);
    std::map<std::string, std::pair<int, double>> seen;
    std::string label;
    int width = 0;
    double value = 0;
    while (lines >> label >> width >> value) seen[label] = {width, value};
    ASSERT_EQ(seen.size(), 4u) << r.output;
    const double a = seen["a"].second;
    ASSERT_GT(a, 0.1) << r.output;
    EXPECT_NEAR(seen["b"].second / a, 2.0, 1e-4) << r.output;        // b's render, not a's
    EXPECT_NEAR(seen["renamed"].second / a, 4.0, 1e-4) << r.output;  // the new render, not the kept one
    EXPECT_EQ(seen["resized"].first, 10) << r.output;
    fs::remove_all(dir);
}

// One order for both fronts (docs/settings.md, "One order"): the source's wavecam.KEY metadata
// over the defaults, a description file over the metadata, the user's flags or hints over both.
// The same file through `wavecam apply` and through oiiotool is the same image: bit for bit for
// the random-phase method's direct sums (tolerance 0; its nufft summation rounds as the
// convolution method does); the convolution method to the float rounding the first test explains.
// The files carry the methods' old words, as files written before the present vocabulary do: both
// fronts take them, name the new word once, and write the new word.
namespace {
// Read afresh: these files are rewritten under the same name within a second, and the shared
// ImageCache would hand back the first one's pixels and header.
void write_tagged(const fs::path& path, const std::string& method) {
    write_render(path.string(), 10, 8, 3.0f, 35.0f);
    OIIO::ImageBuf b = read_float(path);
    OIIO::ImageSpec& spec = b.specmod();
    spec.attribute("wavecam.pinhole", "0.2mm");
    spec.attribute("wavecam.film-distance", "20mm");
    spec.attribute("wavecam.wavelengths", "3");
    spec.attribute("wavecam.runs", 1);  // ints, as wavecam writes them
    spec.attribute("wavecam.film-subsamples", 1);
    spec.attribute("wavecam.seed", "7");
    spec.attribute("wavecam.method", method);
    spec.attribute("wavecam.summation", "direct");
    ASSERT_TRUE(b.write(path.string()));
}
}  // namespace

TEST(Plugin, OneFileGivesOneImageThroughTheCommandAndThePlugin) {
    const fs::path dir = scratch("plugin_one_order");
    for (const auto& [old_word, method] : {std::pair<std::string, std::string>{"exact", "random-phase"},
                                           {"fast", "convolution"}}) {
        const fs::path in = dir / (old_word + ".exr");
        write_tagged(in, old_word);
        const auto cli = run_command(std::string(WAVECAM_BINARY) + " apply " + in.string() + " -o " +
                                     (dir / "cli.exr").string());
        ASSERT_EQ(cli.status, 0) << cli.output;
        EXPECT_NE(cli.output.find("'" + old_word + "' is now called '" + method + "'"), std::string::npos) << cli.output;
        const auto oiio = run_command(kEnv + "oiiotool " + in.string() + ".wavecam -o " + (dir / "oiio.exr").string());
        ASSERT_EQ(oiio.status, 0) << oiio.output;
        const OIIO::ImageBuf a = read_float(dir / "cli.exr"), b = read_float(dir / "oiio.exr");
        for (const OIIO::ImageBuf* out : {&a, &b}) {  // the metadata was read, by both
            EXPECT_EQ(out->spec().get_string_attribute("wavecam.pinhole"), "0.2mm");
            EXPECT_EQ(out->spec().get_string_attribute("wavecam.film-distance"), "20mm");
            EXPECT_EQ(out->spec().get_string_attribute("wavecam.wavelengths"), "450nm,550nm,650nm");
            EXPECT_EQ(out->spec().get_string_attribute("wavecam.method"), method);
        }
        const float tolerance = method == "random-phase" ? 0.0f : 1e-5f;
        const auto cmp = OIIO::ImageBufAlgo::compare(a, b, tolerance, tolerance);
        EXPECT_FALSE(cmp.error) << method;
        EXPECT_EQ(cmp.nfail, 0u) << method << ": max error " << cmp.maxerror;
        EXPECT_EQ(cmp.nwarn, 0u) << method;
        EXPECT_LE(cmp.maxerror, tolerance) << method;
    }
    // the user's flag or hint over the metadata, and over a description file, which is over the metadata
    const fs::path in = dir / "exact.exr";
    std::ofstream(dir / "shot.wavecam") << "source = \"exact.exr\"\npinhole = \"0.3mm\"\n";
    struct Case {
        std::string command, pinhole;
    } cases[] = {
        {std::string(WAVECAM_BINARY) + " apply " + in.string() + " -o " + (dir / "o.exr").string() + " --pinhole 0.25mm",
         "0.25mm"},
        {kEnv + "oiiotool --iconfig wavecam:pinhole 0.25mm " + in.string() + ".wavecam -o " + (dir / "o.exr").string(),
         "0.25mm"},
        {kEnv + "oiiotool " + (dir / "shot.wavecam").string() + " -o " + (dir / "o.exr").string(), "0.3mm"},
        {kEnv + "oiiotool --iconfig wavecam:pinhole 0.25mm " + (dir / "shot.wavecam").string() + " -o " +
             (dir / "o.exr").string(),
         "0.25mm"},
    };
    for (const Case& c : cases) {
        const auto r = run_command(c.command);
        ASSERT_EQ(r.status, 0) << c.command << ": " << r.output;
        const OIIO::ImageBuf out = read_float(dir / "o.exr");
        EXPECT_EQ(out.spec().get_string_attribute("wavecam.pinhole"), c.pinhole) << c.command;
        EXPECT_EQ(out.spec().get_string_attribute("wavecam.film-distance"), "20mm") << c.command;  // the metadata's
        fs::remove(dir / "o.exr");
    }
    fs::remove_all(dir);
}

// Core reports the setting a failure is about; each front words it: flags for the command,
// hints and ?KEY= for the plugin (the plugin's wording: EveryFailureReaches... above).
TEST(Plugin, TheCommandWordsMissingAndBadSettingsAsFlags) {
    const fs::path dir = scratch("plugin_command_words");
    write_render((dir / "nofov.exr").string(), 6, 6, 3.0f, 0.0f);
    write_render((dir / "shot.exr").string(), 6, 6, 3.0f, 35.0f);
    OIIO::ImageBuf tagged = read_float(dir / "shot.exr");
    tagged.specmod().attribute("wavecam.pinhole", "0.2");
    ASSERT_TRUE(tagged.write((dir / "tagged.exr").string()));
    struct Case {
        std::string input, flags, expect;
    } cases[] = {
        {"nofov.exr", "", "nofov.exr: no field of view: the file has no 'wavecam.fov' attribute, and no fov setting "
                          "was given; give it with --fov 50deg"},
        {"shot.exr", "--pinhole 0.2", "--pinhole: expected a length with a unit"},
        {"tagged.exr", "", "tagged.exr: wavecam.pinhole: expected a length with a unit"},
    };
    for (const Case& c : cases) {
        const auto r = run_command(std::string(WAVECAM_BINARY) + " apply " + (dir / c.input).string() + " -o " +
                                   (dir / "o.exr").string() + " --wavelengths 3 " + c.flags);
        EXPECT_NE(r.status, 0) << c.input;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << r.output;
        EXPECT_EQ(r.output.find("wavecam:"), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(dir / "o.exr"));
    }
    fs::remove_all(dir);
}

// An output read back as an input: its wavecam.* header names the same keys the metadata reader
// reads, so a second run with no settings uses the first run's, through either front, and
// reads the output's own colour space and frame (no overscan left to crop).
TEST(Plugin, AnOutputReadBackAsInputKeepsItsSettings) {
    const fs::path dir = scratch("plugin_round_trip");
    write_render((dir / "in.exr").string(), 14, 12, 3.0f, 35.0f);
    auto r = run_command(std::string(WAVECAM_BINARY) + " apply " + (dir / "in.exr").string() + " -o " +
                         (dir / "first.exr").string() +
                         " --pinhole 0.2mm --film-distance 20mm --wavelengths 3 --method random-phase --runs 2 --seed 5"
                         " --summation direct"
                         " --aperture polygon:6:30deg --no-vignetting --output-colorspace ACEScg --overscan 1 --film-subsamples 1");
    ASSERT_EQ(r.status, 0) << r.output;
    // a second diffraction is refused unless asked for, naming the first job
    r = run_command(std::string(WAVECAM_BINARY) + " apply " + (dir / "first.exr").string() + " -o " +
                    (dir / "again.exr").string());
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("already diffracted by wavecam (method random-phase, pinhole 0.2mm"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("--diffract-again"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "again.exr"));
    r = run_command(kEnv + "oiiotool " + (dir / "first.exr").string() + ".wavecam -o " + (dir / "plugin.exr").string());
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("already diffracted by wavecam"), std::string::npos) << r.output;
    r = run_command(std::string(WAVECAM_BINARY) + " apply " + (dir / "first.exr").string() + " -o " +
                    (dir / "again.exr").string() + " --diffract-again");
    ASSERT_EQ(r.status, 0) << r.output;
    r = run_command(kEnv + "oiiotool " + (dir / "first.exr").string() + ".wavecam?diffract-again=true -o " +
                    (dir / "plugin.exr").string());
    ASSERT_EQ(r.status, 0) << r.output;
    const OIIO::ImageBuf first = read_float(dir / "first.exr"), again = read_float(dir / "again.exr"),
                         plugin = read_float(dir / "plugin.exr");
    for (const char* key : {"pinhole", "aperture", "film-distance", "wavelengths", "method", "runs", "seed", "jitter",
                            "vignetting", "depth", "output-colorspace", "fov", "film-subsamples", "summation"}) {
        const std::string name = std::string("wavecam.") + key;
        ASSERT_NE(first.spec().find_attribute(name), nullptr) << name;
        for (const OIIO::ImageBuf* out : {&again, &plugin})
            EXPECT_EQ(out->spec().get_string_attribute(name), first.spec().get_string_attribute(name)) << name;
    }
    EXPECT_EQ(first.spec().width, 12);  // the overscan was cropped once, not again
    EXPECT_EQ(again.spec().width, 12);
    EXPECT_EQ(again.spec().get_string_attribute("wavecam.input-colorspace"), "ACEScg");
    const auto cmp = OIIO::ImageBufAlgo::compare(again, plugin, 0.0f, 0.0f);
    EXPECT_EQ(cmp.nfail, 0u) << cmp.maxerror;
    fs::remove_all(dir);
}
