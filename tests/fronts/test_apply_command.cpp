// `wavecam apply` as a user runs it: outputs, header, and every bad input (docs/errors.md).
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <sched.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <limits>
#include <set>
#include <thread>

#include "command_runner.h"
#include "wavecam/diffract_image.h"

namespace fs = std::filesystem;
using namespace wavecam::test;

namespace {
const std::string kWavecam = WAVECAM_BINARY;
// small and quick: 3 wavelengths, 1 run
const std::string kQuick = " --film-distance 20mm --pinhole 0.2mm --wavelengths 3 --runs 1 ";

std::string file_bytes(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
}

// A random-phase job of 2 runs on `input` through `summation`, its output path to follow (a 0.05 mm
// pinhole: a sixteenth of the 0.2 mm one's samples, for the direct sums' sake).
std::string small_random_phase_job(const fs::path& input, const std::string& summation) {
    return " apply " + input.string() +
           " --method random-phase --runs 2 --seed 3 --film-distance 20mm --pinhole 0.05mm --wavelengths 3"
           " --summation " +
           summation + " -o ";
}
}  // namespace

TEST(ApplyCommand, WritesRgbAndKeepsTheDepthChannel) {
    const fs::path dir = scratch("apply_ok");
    write_render((dir / "in.exr").string(), 12, 10, 2.0f, 30.0f);
    const auto r = run_command(kWavecam + " apply " + (dir / "in.exr").string() + " -o " + (dir / "out.exr").string() +
                               kQuick + "--compare " + (dir / "sheet.png").string());
    ASSERT_EQ(r.status, 0) << r.output;
    OIIO::ImageBuf out((dir / "out.exr").string());
    ASSERT_TRUE(out.read());
    const auto& spec = out.spec();
    ASSERT_EQ(spec.nchannels, 4);
    EXPECT_EQ(spec.channelnames[3], "Z");
    EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(spec.get_string_attribute("wavecam.pinhole"), "0.2mm");
    EXPECT_EQ(spec.get_string_attribute("wavecam.film-distance"), "20mm");
    EXPECT_EQ(spec.get_string_attribute("wavecam.wavelengths"), "450nm,550nm,650nm");
    for (int j = 0; j < 10; ++j)
        for (int i = 0; i < 12; ++i) EXPECT_EQ(out.getchannel(i, j, 0, 3), 2.0f);
    EXPECT_TRUE(fs::exists(dir / "sheet.png"));
    fs::remove_all(dir);
}

TEST(ApplyCommand, RunsWithNoFlagsWhenTheFileHasItsFieldOfView) {
    const fs::path dir = scratch("apply_defaults");
    write_render((dir / "in.exr").string(), 8, 8, 5.0f, 40.0f);
    const auto r = run_command(kWavecam + " apply " + (dir / "in.exr").string() + " -o " + (dir / "out.exr").string());
    ASSERT_EQ(r.status, 0) << r.output;
    OIIO::ImageBuf out((dir / "out.exr").string());
    ASSERT_TRUE(out.read());
    // the default pinhole is Rayleigh's optimum 1.9 sqrt(f lambda), f = 50 mm, 550 nm
    EXPECT_EQ(out.spec().get_string_attribute("wavecam.pinhole").substr(0, 5), "0.315");
    fs::remove_all(dir);
}

// The seed paper's setting: one wavelength is monochromatic light - a grey render stays grey
// and the header says so; a non-circular aperture is named in the header as given.
TEST(ApplyCommand, OneWavelengthIsMonochromeAndApertureShapesReachTheHeader) {
    const fs::path dir = scratch("apply_mono");
    const std::string in = (dir / "in.exr").string(), out = (dir / "out.exr").string();
    {
        OIIO::ImageSpec spec(10, 8, 4, OIIO::TypeDesc::FLOAT);
        spec.channelnames = {"R", "G", "B", "Z"};
        spec.attribute("wavecam.fov", 30.0f);
        OIIO::ImageBuf buf(spec);
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 10; ++i) {
                const float g = 0.1f + 0.08f * ((i * 7 + j * 3) % 10);  // a grey pattern
                const float px[4] = {g, g, g, 2.0f};
                buf.setpixel(i, j, px);
            }
        ASSERT_TRUE(buf.write(in));
    }
    for (const std::string method : {"convolution", "random-phase"}) {
        const auto r = run_command(kWavecam + " apply " + in + " -o " + out +
                                   " --film-distance 20mm --pinhole 0.2mm --runs 1 --wavelengths 550nm --aperture "
                                   "polygon:6:30deg --method " + method);
        ASSERT_EQ(r.status, 0) << r.output;
        OIIO::ImageBuf img(out);
        ASSERT_TRUE(img.read());
        EXPECT_NE(img.spec().get_string_attribute("wavecam.light").find("monochrome"), std::string::npos);
        EXPECT_EQ(img.spec().get_string_attribute("wavecam.aperture"), "polygon:6:30deg");
        EXPECT_EQ(img.spec().get_string_attribute("wavecam.wavelengths"), "550nm");
        double spread = 0, level = 0;
        for (int j = 0; j < 8; ++j)
            for (int i = 0; i < 10; ++i) {
                const float r0 = img.getchannel(i, j, 0, 0), g0 = img.getchannel(i, j, 0, 1), b0 = img.getchannel(i, j, 0, 2);
                spread = std::max({spread, double(std::fabs(r0 - g0)), double(std::fabs(b0 - g0))});
                level = std::max(level, double(g0));
            }
        EXPECT_GT(level, 0.0) << method;
        EXPECT_LT(spread, 1e-4 * level) << method << ": grey in, grey out";
    }
    fs::remove_all(dir);
}

TEST(ApplyCommand, BadInputsGetAClearErrorAndNoOutput) {
    const fs::path dir = scratch("apply_bad");
    const std::string good = (dir / "good.exr").string();
    write_render(good, 8, 8, 2.0f, 30.0f);
    write_render((dir / "nodepth.exr").string(), 8, 8, 2.0f, 30.0f, {"R", "G", "B", "A"});
    write_render((dir / "nofov.exr").string(), 8, 8, 2.0f, 0.0f);
    write_render((dir / "negative.exr").string(), 8, 8, -1.0f, 30.0f);
    write_render((dir / "tiny.exr").string(), 1, 1, 2.0f, 30.0f);
    write_render((dir / "zero.exr").string(), 8, 8, 0.0f, 30.0f);
    write_render((dir / "widefov.exr").string(), 8, 8, 2.0f, 200.0f);
    {
        OIIO::ImageBuf black(OIIO::ImageSpec(4, 4, 1, OIIO::TypeDesc::UINT8));  // zero-filled
        ASSERT_TRUE(black.write((dir / "black.png").string()));
    }
    {
        OIIO::ImageBuf nan(good);
        nan.read(0, 0, true);
        const float bad = std::numeric_limits<float>::quiet_NaN();
        nan.setpixel(3, 2, std::vector<float>{bad, 0, 0, 2}.data());
        nan.write((dir / "nan.exr").string());
        nan.setpixel(3, 2, std::vector<float>{0.5f, std::numeric_limits<float>::infinity(), 0, 2}.data());
        nan.write((dir / "inf.exr").string());
        nan.setpixel(3, 2, std::vector<float>{0.5f, 0.5f, 3e38f, 2}.data());  // finite; its sums overflow
        nan.write((dir / "huge.exr").string());
        nan.setpixel(3, 2, std::vector<float>{0.5f, 0.5f, 0.5f, bad}.data());
        nan.write((dir / "nandepth.exr").string());
    }
    std::ofstream((dir / "text.exr").string()) << "not an image";
    const std::string deep = (dir / "deep.exr").string();  // samples per pixel: crashed wavecam before
    {
        OIIO::ImageBuf samples = OIIO::ImageBufAlgo::deepen(OIIO::ImageBuf(good));
        ASSERT_TRUE(samples.deep() && samples.write(deep)) << samples.geterror();
        // an OIIO application handing the library a deep buffer gets the library's own error
        OIIO::ImageBuf out;
        EXPECT_FALSE(wavecam::diffract(out, samples, "deep.exr", {}));
        EXPECT_NE(out.geterror().find("deep.exr: deep image (samples per pixel) is not supported"), std::string::npos)
            << out.geterror();
    }
    {
        const std::string bytes = file_bytes(good);
        std::ofstream((dir / "truncated.exr").string(), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    }
    struct Case {
        std::string input, extra, expect;
    } cases[] = {
        {"nodepth.exr", "", "channel 'Z'"},
        {"nofov.exr", "", "nofov.exr: no field of view"},
        {"negative.exr", "", "channel 'Z' at pixel (0, 0) is -1, expected a distance > 0"},
        {"nan.exr", "", "pixel (3, 2)"},
        {"inf.exr", "", "expected finite radiance"},
        {"huge.exr", "", "channel 'B' at pixel (3, 2) is 3e+38, expected finite radiance within +-1e30"},
        {"nandepth.exr", "", "channel 'Z' at pixel (3, 2)"},
        {"zero.exr", "", "expected a distance > 0"},
        {"widefov.exr", "", "wavecam.fov is 200 degrees, expected a field of view between 0 and 180"},
        {"tiny.exr", "", "at least 2x2"},
        {"text.exr", "", "text.exr"},
        {"truncated.exr", "", "truncated.exr"},
        {"missing.exr", "", "missing.exr"},
        {"deep.exr", "", "deep.exr: cannot be read as an image (a deep image; expected a flat one)"},
        {"good.exr", "--aperture mask:" + deep, "deep.exr: cannot be read as an image (a deep image"},
        {"good.exr", "--pinhole 0.2", "--pinhole: expected a length"},
        {"good.exr", "--wavelengths 0", "--wavelengths"},
        {"good.exr", "--aperture polygon:2", "--aperture: expected the number of sides N"},
        {"good.exr", "--aperture zoneplate:0", "--aperture: expected the number of zones N"},
        {"good.exr", "--aperture sieve:2", "--aperture: a photon sieve needs N >= 3 zones"},
        {"good.exr", "--aperture mask:no_such_mask.png", "no_such_mask.png"},
        {"good.exr", "--aperture mask:" + (dir / "black.png").string(), "lets no light through"},
        {"good.exr", "--aperture hexagon", "polygon:N"},
        {"good.exr", "--depth sideways", "--depth"},
        {"good.exr", "--output-colorspace NoSuchSpace", "NoSuchSpace"},
        {"good.exr", "--method random-phase --runs 100000 --wavelengths 64 --max-terms 1e9", "raise --max-terms"},
        {"good.exr", "--method sideways", "--method"},
        {"good.exr", "--max-memory 1KiB", "raise --max-memory (e.g. --max-memory 32GiB)"},
        {"good.exr", "--max-memory 12", "--max-memory: expected a size"},
    };
    // kQuick with the case's settings in place of its own (each option is given once)
    auto quick_with = [](const std::string& extra) {
        std::istringstream words(kQuick);
        std::string job, key, value;
        while (words >> key >> value)
            if (extra.find(key + " ") == std::string::npos) job += " " + key + " " + value;
        return job + " " + extra;
    };
    for (const Case& c : cases) {
        const fs::path out = dir / "out.exr";
        const auto r = run_command(kWavecam + " apply " + (dir / c.input).string() + " -o " + out.string() +
                                   quick_with(c.extra));
        EXPECT_NE(r.status, 0) << c.input << " " << c.extra;
        EXPECT_NE(r.output.find(c.expect), std::string::npos) << c.input << " " << c.extra << ": " << r.output;
        EXPECT_FALSE(fs::exists(out)) << c.input << " " << c.extra;
    }
    // the output would overwrite the input: refused, input untouched
    const std::string before = file_bytes(good);
    const auto r = run_command(kWavecam + " apply " + good + " -o " + good + kQuick);
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("is the same file as the render"), std::string::npos) << r.output;
    EXPECT_EQ(file_bytes(good), before);
    // an unwritable output: error names it, nothing left behind
    const auto w = run_command(kWavecam + " apply " + good + " -o /nonexistent-dir/out.exr" + kQuick);
    EXPECT_NE(w.status, 0);
    EXPECT_NE(w.output.find("/nonexistent-dir/out.exr"), std::string::npos) << w.output;
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
    fs::remove_all(dir);
}

// SIGINT or SIGTERM during a long run: prompt stop, non-zero status, no output file.
TEST(ApplyCommand, InterruptStopsPromptlyAndLeavesNothing) {
    const fs::path dir = scratch("apply_interrupt");
    write_render((dir / "in.exr").string(), 64, 64, 2.0f, 30.0f);
    const fs::path out = dir / "out.exr";
    for (const char* signal : {"INT", "TERM"}) {
        // the random-phase method on this image takes minutes; it is stopped after three seconds (a
        // loaded machine, or a sanitizer build, can take more than one just to load the libraries
        // and install the handler) and must then stop within two
        const auto start = std::chrono::steady_clock::now();
        const auto r = run_command("timeout -s " + std::string(signal) + " 3 " + kWavecam + " apply " +
                                   (dir / "in.exr").string() + " -o " + out.string() +
                                   " --method random-phase --runs 20 --wavelengths 16 --film-subsamples 3");
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        EXPECT_NE(r.status, 0) << signal;
        EXPECT_NE(r.output.find("interrupted"), std::string::npos) << signal << ": " << r.output;
        EXPECT_LT(seconds, 5.0) << signal << ": stopped " << seconds - 3 << " s after the signal";
        EXPECT_FALSE(fs::exists(out)) << signal;
    }
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().filename(), "in.exr");
    fs::remove_all(dir);
}

TEST(ApplyCommand, FrameRangesWithHashAndPrintfPatterns) {
    const fs::path dir = scratch("apply_frames");
    for (int f = 1; f <= 3; ++f) {
        char name[32];
        std::snprintf(name, sizeof name, "shot.%04d.exr", f);
        write_render((dir / name).string(), 6, 6, 2.0f, 30.0f);
    }
    auto r = run_command(kWavecam + " apply " + (dir / "shot.#.exr").string() + " -o " + (dir / "out.%04d.exr").string() +
                         " --frames 1-3" + kQuick);
    ASSERT_EQ(r.status, 0) << r.output;
    for (int f = 1; f <= 3; ++f) EXPECT_TRUE(fs::exists(dir / ("out.000" + std::to_string(f) + ".exr")));
    r = run_command(kWavecam + " apply " + (dir / "shot.#.exr").string() + " -o " + (dir / "same.exr").string() +
                    " --frames 1-3" + kQuick);
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("--frames"), std::string::npos) << r.output;
    r = run_command(kWavecam + " apply " + (dir / "shot.#.exr").string() + " -o " + (dir / "o.#.exr").string() +
                    " --frames 4-5" + kQuick);  // a missing frame: stops, names the file
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("shot.0004.exr"), std::string::npos) << r.output;
    fs::remove_all(dir);
}

// Frames run in ascending order, each once: steps keep their OIIO meaning (x: every STEPth frame
// from FIRST, y: the others), and what OIIO would enumerate downwards or twice is refused in
// words before any work.
TEST(ApplyCommand, FrameRangesRunAscendingOrAreRefused) {
    const fs::path dir = scratch("apply_frame_order");
    for (int f = 1; f <= 3; ++f) write_render((dir / ("shot.000" + std::to_string(f) + ".exr")).string(), 6, 6, 2.0f, 30.0f);
    const std::string apply = kWavecam + " apply " + (dir / "shot.#.exr").string() + " -o " + (dir / "o.#.exr").string() + kQuick;
    const struct {
        std::string frames;
        std::vector<int> written;
    } runs[] = {{"1-3x2", {1, 3}}, {"1-3y2", {2}}, {"2,3", {2, 3}}};
    for (const auto& run : runs) {
        const auto r = run_command(apply + " --frames " + run.frames);
        ASSERT_EQ(r.status, 0) << run.frames << ": " << r.output;
        for (int f = 1; f <= 3; ++f) {
            const fs::path out = dir / ("o.000" + std::to_string(f) + ".exr");
            const bool expected = std::find(run.written.begin(), run.written.end(), f) != run.written.end();
            EXPECT_EQ(fs::exists(out), expected) << run.frames << ": frame " << f;
            fs::remove(out);
        }
    }
    const struct {
        std::string frames, message;
    } refused[] = {
        {"3-1", "--frames: '3-1' runs backwards; expected FIRST-LAST with FIRST <= LAST, e.g. 1-3"},
        {"1,3-2", "--frames: '3-2' (in '1,3-2') runs backwards"},
        {"3-1x1", "--frames: '3-1x1' runs backwards"},
        {"3-1x-1", "--frames: '3-1x-1' has a step of -1; expected FIRST-LASTxSTEP with a step of 1 or more"},
        {"1-3x-2", "--frames: '1-3x-2' has a step of -2"},
        {"1-3x0", "--frames: '1-3x0' has a step of 0"},
        {"3,1", "--frames: '3,1' lists frame 1 after frame 3; expected each frame once, in ascending order"},
        {"1-3,2", "--frames: '1-3,2' lists frame 2 after frame 3"},
        {"2,2", "--frames: '2,2' lists frame 2 twice"},
    };
    for (const auto& row : refused) {
        const auto r = run_command(apply + " --frames " + row.frames);
        EXPECT_EQ(WEXITSTATUS(r.status), 2) << row.frames << ": " << r.output;
        EXPECT_NE(r.output.find(row.message), std::string::npos) << row.frames << ": " << r.output;
        for (int f = 1; f <= 3; ++f) EXPECT_FALSE(fs::exists(dir / ("o.000" + std::to_string(f) + ".exr"))) << row.frames;
    }
    fs::remove_all(dir);
}

// depth-scale: one unit of the depth channel is that long. A render in centimetres with
// --depth-scale 1cm (or its own wavecam.depth-scale metadata) is diffracted exactly as the same
// render in metres; the depth channel is kept as the input had it and the header records the
// scale, so the output read back gives the same metres. Bad scales are refused.
TEST(ApplyCommand, DepthScaleTurnsTheDepthChannelIntoMetres) {
    const fs::path dir = scratch("apply_depth_scale");
    const auto p = [&dir](const std::string& name) { return (dir / name).string(); };
    write_render(p("m.exr"), 12, 10, 0.04f, 30.0f);  // 4 cm from the pinhole: depth shapes the PSF
    write_render(p("cm.exr"), 12, 10, 4.0f, 30.0f);
    {
        OIIO::ImageBuf tagged(p("cm.exr"));
        ASSERT_TRUE(tagged.read(0, 0, true));
        tagged.specmod().attribute("wavecam.depth-scale", "1cm");
        ASSERT_TRUE(tagged.write(p("cm_tagged.exr")));
    }
    const std::string opts = " --film-distance 20mm --pinhole 0.2mm --wavelengths 3 ";
    auto apply = [&](const std::string& in, const std::string& out, const std::string& extra) {
        const auto r = run_command(kWavecam + " apply " + p(in) + " -o " + p(out) + opts + extra);
        EXPECT_EQ(r.status, 0) << r.output;
    };
    apply("m.exr", "out_m.exr", "");
    apply("cm.exr", "out_cm.exr", "--depth-scale 1cm");
    apply("cm_tagged.exr", "out_tagged.exr", "");
    apply("cm.exr", "out_plain.exr", "");  // read as 4 m
    // read back, each output is diffracted with its own settings: the cm one's recorded scale included
    apply("out_cm.exr", "again_cm.exr", "--diffract-again");
    apply("out_m.exr", "again_m.exr", "--diffract-again");
    OIIO::ImageBuf m(p("out_m.exr")), cm(p("out_cm.exr")), tagged(p("out_tagged.exr")), plain(p("out_plain.exr")),
        again(p("again_cm.exr")), again_m(p("again_m.exr"));
    for (auto* b : {&m, &cm, &tagged, &plain, &again, &again_m})
        ASSERT_TRUE(b->read(0, 0, true, OIIO::TypeDesc::FLOAT));
    OIIO::ROI rgb = m.roi();
    rgb.chend = 3;
    EXPECT_LE(OIIO::ImageBufAlgo::compare(cm, m, 1e-6f, 1e-6f, rgb).maxerror, 1e-6);
    EXPECT_LE(OIIO::ImageBufAlgo::compare(tagged, m, 1e-6f, 1e-6f, rgb).maxerror, 1e-6);
    EXPECT_LE(OIIO::ImageBufAlgo::compare(again, again_m, 1e-6f, 1e-6f, rgb).maxerror, 1e-6);
    // 4 cm against 4 m: both PSFs are under a pixel wide here (0.3 and 0.2 mm on 0.9 mm pixels), so
    // depth moves the image by about 8e-4; the same image would agree to 1e-6, as above
    EXPECT_GT(OIIO::ImageBufAlgo::compare(plain, m, 1e-6f, 1e-6f, rgb).maxerror, 1e-4) << "depth made no difference";
    EXPECT_EQ(cm.spec().get_string_attribute("wavecam.depth-scale"), "0.01m");
    EXPECT_EQ(m.spec().get_string_attribute("wavecam.depth-scale"), "1m");
    EXPECT_EQ(cm.getchannel(3, 3, 0, 3), 4.0f);  // the depth channel as the input had it
    for (const auto& [scale, expected] : std::vector<std::pair<std::string, std::string>>{
             {"0cm", "--depth-scale: expected a length > 0 (one depth unit of the render, e.g. 1cm), got '0cm'"},
             {"-1cm", "--depth-scale: expected a length > 0 (one depth unit of the render, e.g. 1cm), got '-1cm'"},
             {"1e400m", "--depth-scale: expected a length with a unit (nm, um, mm, cm, m), e.g. 0.3mm, got '1e400m'"},
             {"2.54", "--depth-scale: expected a length with a unit (nm, um, mm, cm, m), e.g. 0.3mm, got '2.54'"}}) {
        const auto r = run_command(kWavecam + " apply " + p("cm.exr") + " -o " + p("bad.exr") + opts +
                                   "--depth-scale " + scale);
        EXPECT_NE(r.status, 0) << scale;
        EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(p("bad.exr")));
    }
    fs::remove_all(dir);
}

// A job's threads: --threads, else OMP_NUM_THREADS (what hosts and farms set), else the CPUs the
// process may run on; `wavecam estimate` says how many. That they sleep when they wait is
// tests/core/test_parallel.cpp's; that their number changes no image, the test below.
TEST(ApplyCommand, TheThreadsComeFromTheFlagElseOmpNumThreads) {
    auto threads = [&](const std::string& env, const std::string& flags) {
        const auto r = run_command("env -u OMP_NUM_THREADS " + env + " " + kWavecam +
                                   " estimate --size 16x12 --fov 30deg --nearest 2m" + flags);
        EXPECT_EQ(r.status, 0) << r.output;
        const size_t at = r.output.find("threads: ");
        return at == std::string::npos ? r.output : r.output.substr(at, r.output.find(',', at) - at);
    };
    cpu_set_t cpus;
    ASSERT_EQ(sched_getaffinity(0, sizeof(cpus), &cpus), 0);
    EXPECT_EQ(threads("", ""), "threads: " + std::to_string(CPU_COUNT(&cpus)));
    EXPECT_EQ(threads("OMP_NUM_THREADS=3", ""), "threads: 3");
    EXPECT_EQ(threads("OMP_NUM_THREADS=3", " --threads 5"), "threads: 5");
}

// One word, one meaning, and nothing in the environment changes an image: the methods' and the
// summations' words share none; a random-phase run through each evaluator gives the same pixels
// whatever the environment holds (a variable that once chose the evaluator, the thread count).
TEST(ApplyCommand, TheEnvironmentChangesNoImageAndNoWordMeansTwoThings) {
    const fs::path dir = scratch("apply_environment");
    write_render((dir / "in.exr").string(), 16, 12, 2.0f, 30.0f);
    for (const std::string summation : {"auto", "direct", "nufft", "kernel"}) {
        const std::string args = small_random_phase_job(dir / "in.exr", summation);
        const auto plain = run_command(kWavecam + args + (dir / "plain.exr").string());
        ASSERT_EQ(plain.status, 0) << plain.output;
        const auto other = run_command("WAVECAM_SUMMATION=direct OMP_NUM_THREADS=1 " + kWavecam + args +
                                       (dir / "other.exr").string());
        ASSERT_EQ(other.status, 0) << other.output;
        OIIO::ImageBuf a((dir / "plain.exr").string()), b((dir / "other.exr").string());
        const auto cmp = OIIO::ImageBufAlgo::compare(a, b, 0.0f, 0.0f);
        EXPECT_EQ(cmp.nfail, 0u) << summation << ": max difference " << cmp.maxerror;
        EXPECT_EQ(a.spec().get_string_attribute("wavecam.summation"), summation);
    }
    // the words each key takes, from its own error message: none in common
    auto words = [&](const std::string& key) {
        const auto r = run_command(kWavecam + " apply " + (dir / "in.exr").string() + " -o " +
                                   (dir / "x.exr").string() + " --" + key + " nonsense");
        EXPECT_NE(r.status, 0);
        std::set<std::string> found;
        for (size_t at = r.output.find('\''); at != std::string::npos; at = r.output.find('\'', at + 1)) {
            const size_t end = r.output.find('\'', at + 1);
            if (end == std::string::npos) break;
            found.insert(r.output.substr(at + 1, end - at - 1));
            at = end;
        }
        found.erase("nonsense");
        return found;
    };
    const std::set<std::string> methods = words("method"), summations = words("summation");
    EXPECT_EQ(methods, (std::set<std::string>{"convolution", "random-phase", "incoherent"}));
    EXPECT_EQ(summations, (std::set<std::string>{"auto", "direct", "nufft", "kernel"}));
    // the kernel summation's old word is still taken, with a note naming the new one
    const auto old = run_command(kWavecam + small_random_phase_job(dir / "in.exr", "psf") + (dir / "old.exr").string());
    ASSERT_EQ(old.status, 0) << old.output;
    EXPECT_NE(old.output.find("'psf' is now called 'kernel'"), std::string::npos) << old.output;
    EXPECT_EQ(OIIO::ImageBuf((dir / "old.exr").string()).spec().get_string_attribute("wavecam.summation"), "kernel");
    fs::remove_all(dir);
}
