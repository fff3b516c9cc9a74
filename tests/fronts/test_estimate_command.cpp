// `wavecam estimate` as a user runs it: a render, or a description of one before it exists,
// priced as `wavecam apply` prices the render (the same job line and terms), and every bad input.
#include <gtest/gtest.h>

#include <regex>
#include <string>

#include "command_runner.h"

namespace fs = std::filesystem;
using namespace wavecam::test;

namespace {
const std::string kWavecam = WAVECAM_BINARY;
const std::string kJob = " --film-distance 20mm --pinhole 0.2mm --wavelengths 3 --method random-phase --runs 4 ";

// The terms of a line "... JOB = 1.2e+09 terms, about ..." (a refusal's as well); -1 if none.
double terms_of(const std::string& output) {
    std::smatch m;
    return std::regex_search(output, m, std::regex(" = ([0-9.e+-]+) terms, about ")) ? std::stod(m[1]) : -1;
}

// The job line: what precedes " = N terms".
std::string job_of(const std::string& output) {
    std::smatch m;
    return std::regex_search(output, m, std::regex(": ([^:\n]*pixels x [^\n]*) = [0-9.e+-]+ terms")) ? m[1].str() : "";
}
}  // namespace

// At a narrow and a wide field: the description's terms and job line are the render's, and the
// ones apply refuses the render with.
TEST(EstimateCommand, ADescribedFrameCostsWhatItsRenderCosts) {
    const fs::path dir = scratch("estimate_same");
    for (const float fov : {10.0f, 60.0f}) {
        const std::string render = (dir / "in.exr").string();
        write_render(render, 40, 30, 2.0f, fov);
        const std::string deg = " --fov " + std::to_string(fov) + "deg";
        const auto file = run_command(kWavecam + " estimate " + render + kJob);
        const auto described = run_command(kWavecam + " estimate --size 40x30 --nearest 2m" + deg + kJob);
        const auto apply = run_command(kWavecam + " apply " + render + " -o " + (dir / "out.exr").string() + kJob +
                                       "--max-terms 1");
        ASSERT_EQ(file.status, 0) << file.output;
        ASSERT_EQ(described.status, 0) << described.output;
        EXPECT_NE(apply.status, 0) << apply.output;
        ASSERT_GT(terms_of(file.output), 0) << file.output;
        EXPECT_EQ(terms_of(described.output), terms_of(file.output)) << described.output << file.output;
        // (the estimate prints three digits)
        EXPECT_NEAR(terms_of(apply.output) / terms_of(file.output), 1.0, 5e-3) << apply.output << file.output;
        EXPECT_EQ(job_of(described.output), job_of(file.output));
        EXPECT_NE(file.output.find("MiB at the peak"), std::string::npos) << file.output;
        EXPECT_FALSE(fs::exists(dir / "out.exr"));
    }
    fs::remove_all(dir);
}

// --nearest is a length in metres, whatever the depth channel's unit: a scene in centimetres
// costs what the same scene in metres costs; farther sources (inf: sky) cost no more.
TEST(EstimateCommand, TheNearestDepthIsInMetresWhateverTheDepthScale) {
    const std::string frame = " estimate --size 32x24 --fov 60deg --nearest 0.5m" + kJob;
    const auto metres = run_command(kWavecam + frame);
    const auto centimetres = run_command(kWavecam + frame + "--depth-scale 1cm");
    const auto sky = run_command(kWavecam + " estimate --size 32x24 --fov 60deg --nearest inf" + kJob);
    ASSERT_EQ(metres.status, 0) << metres.output;
    ASSERT_EQ(centimetres.status, 0) << centimetres.output;
    ASSERT_EQ(sky.status, 0) << sky.output;
    EXPECT_EQ(terms_of(centimetres.output), terms_of(metres.output)) << centimetres.output << metres.output;
    EXPECT_GT(terms_of(sky.output), 0) << sky.output;
    EXPECT_LE(terms_of(sky.output), terms_of(metres.output)) << sky.output << metres.output;
}

TEST(EstimateCommand, AJobBeyondItsLimitsIsRefusedAsApplyRefusesIt) {
    const auto terms = run_command(kWavecam + " estimate --size 64x48 --fov 50deg --nearest 2m" + kJob +
                                   "--max-terms 1e6");
    EXPECT_EQ(WEXITSTATUS(terms.status), 1) << terms.output;
    EXPECT_NE(terms.output.find("beyond the max-terms limit of 1e+06"), std::string::npos) << terms.output;
    EXPECT_NE(terms.output.find("64x48 frame: "), std::string::npos) << terms.output;
    const auto memory = run_command(kWavecam + " estimate --size 64x48 --fov 50deg --nearest 2m" + kJob +
                                    "--max-memory 1KiB");
    EXPECT_EQ(WEXITSTATUS(memory.status), 1) << memory.output;
    EXPECT_NE(memory.output.find("beyond the max-memory limit"), std::string::npos) << memory.output;
}

TEST(EstimateCommand, TheConvolutionMethodIsNotTimed) {
    const auto r = run_command(kWavecam + " estimate --size 64x48 --fov 50deg --nearest 2m");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("64x48 pixels x 8 wavelengths, convolution method: no scene sums"), std::string::npos)
        << r.output;
    EXPECT_EQ(terms_of(r.output), -1) << r.output;
    EXPECT_NE(r.output.find("MiB at the peak"), std::string::npos) << r.output;
}

TEST(EstimateCommand, BadDescriptionsAreRefusedNamingTheFlag) {
    const fs::path dir = scratch("estimate_bad");
    write_render((dir / "in.exr").string(), 8, 8, 2.0f, 40.0f);
    const struct {
        std::string args, expected;
    } cases[] = {
        {" --size 64by48 --nearest 2m --fov 50deg", "--size: expected WIDTHxHEIGHT in pixels, each 1 to 16384"},
        {" --size 0x48 --nearest 2m --fov 50deg", "--size: expected WIDTHxHEIGHT"},
        {" --size 64x48 --nearest 2 --fov 50deg", "--nearest"},
        {" --size 64x48 --fov 50deg", "a described frame needs --size"},
        {" --size 64x48 --nearest 2m", "a described frame needs --size"},
        {" " + (dir / "in.exr").string() + " --size 64x48 --nearest 2m", "not both"},
        {"", "expected a render"},
        {" " + (dir / "missing.exr").string(), "missing.exr"},
    };
    for (const auto& c : cases) {
        const auto r = run_command(kWavecam + " estimate" + c.args);
        EXPECT_EQ(WEXITSTATUS(r.status), 2) << c.args << ": " << r.output;
        EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.args << ": " << r.output;
    }
    fs::remove_all(dir);
}
