// `wavecam psf` as a user runs it: the EXR it writes, its header, and its errors.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {
struct CommandRun {
    int status;
    std::string output;
};

CommandRun run(const std::string& args) {
    const std::string cmd = std::string(WAVECAM_BINARY) + " " + args + " 2>&1";
    CommandRun r{0, {}};
    FILE* p = popen(cmd.c_str(), "r");
    char buf[512];
    while (fgets(buf, sizeof buf, p)) r.output += buf;
    r.status = pclose(p);
    return r;
}

fs::path temp_dir() {
    fs::path d = fs::temp_directory_path() / ("wavecam_psf_cmd_" + std::to_string(::getpid()));
    fs::create_directories(d);
    return d;
}
}  // namespace

TEST(PsfCommand, WritesRelativeIrradianceWithParametersInTheHeader) {
    const fs::path dir = temp_dir();
    const fs::path exr = dir / "psf.exr", png = dir / "psf.png";
    const CommandRun r = run("psf --pinhole 40um --film-distance 10mm --wavelength 500nm --film-size 0.1mm "
                      "--resolution 21 -o " + exr.string() + " --png " + png.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("Fresnel number"), std::string::npos);
    EXPECT_NE(r.output.find("pinhole samples"), std::string::npos);
    OIIO::ImageBuf buf(exr.string());
    ASSERT_TRUE(buf.read()) << buf.geterror();
    const auto& spec = buf.spec();
    EXPECT_EQ(spec.width, 21);
    EXPECT_EQ(spec.nchannels, 1);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(spec.get_string_attribute("wavecam.pinhole"), "0.04mm");
    EXPECT_EQ(spec.get_string_attribute("wavecam.wavelength"), "500nm");
    EXPECT_EQ(spec.get_string_attribute("wavecam.source-distance"), "inf");
    // centre pixel: 4 sin^2(pi N / 2), N = a^2 / (lambda f) = 0.08 (independent of the command)
    const double n = std::pow(20e-6, 2) / (500e-9 * 10e-3);
    float centre = 0;
    buf.getpixel(10, 10, &centre, 1);
    EXPECT_NEAR(centre, 4 * std::pow(std::sin(M_PI * n / 2), 2), 0.01);
    EXPECT_TRUE(fs::exists(png));
    fs::remove_all(dir);
}

// A zone plate: the command states its first focus r_1^2 / lambda (here (0.1 mm)^2 / 4 / 500 nm
// = 5 mm), in the output and the header, and the plate focuses there: at the focus the centre
// is far brighter than the unobstructed wave.
TEST(PsfCommand, ZonePlateStatesItsFocus) {
    const fs::path dir = temp_dir();
    const fs::path exr = dir / "zp.exr";
    const CommandRun r = run("psf --aperture zoneplate:4 --pinhole 0.2mm --film-distance 5mm --wavelength 500nm "
                             "--film-size 0.02mm --resolution 5 -o " + exr.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("first focus r1^2/lambda = 5 mm"), std::string::npos) << r.output;
    OIIO::ImageBuf buf(exr.string());
    ASSERT_TRUE(buf.read()) << buf.geterror();
    EXPECT_EQ(buf.spec().get_string_attribute("wavecam.aperture"), "zoneplate:4");
    EXPECT_EQ(buf.spec().get_string_attribute("wavecam.zoneplate-focus"), "5mm");
    float centre = 0;
    buf.getpixel(2, 2, &centre, 1);
    EXPECT_GT(centre, 10);  // two open zones in phase: about (2 x 2)^2 = 16
    fs::remove_all(dir);
}

// A photon sieve: the same focus r_1^2 / lambda, stated the same way; at the focus the ring of
// holes on zone 3 adds in phase with the central disc, so the centre beats the disc's own 4.
TEST(PsfCommand, PhotonSieveStatesItsFocus) {
    const fs::path dir = temp_dir();
    const fs::path exr = dir / "sieve.exr";
    const CommandRun r = run("psf --aperture sieve:4 --pinhole 0.2mm --film-distance 5mm --wavelength 500nm "
                             "--film-size 0.02mm --resolution 5 -o " + exr.string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("photon sieve    first focus r1^2/lambda = 5 mm"), std::string::npos) << r.output;
    OIIO::ImageBuf buf(exr.string());
    ASSERT_TRUE(buf.read()) << buf.geterror();
    EXPECT_EQ(buf.spec().get_string_attribute("wavecam.aperture"), "sieve:4:1.5x:50%:1");
    EXPECT_EQ(buf.spec().get_string_attribute("wavecam.zoneplate-focus"), "5mm");
    float centre = 0;
    buf.getpixel(2, 2, &centre, 1);
    EXPECT_GT(centre, 6);
    fs::remove_all(dir);
}

TEST(PsfCommand, BadFlagsGetOneLineNamingTheFlag) {
    const fs::path dir = temp_dir();
    const fs::path exr = dir / "bad.exr";
    struct Case {
        const char* args;
        const char* flag;
    } cases[] = {{"--pinhole 0.3", "--pinhole"},
                 {"--pinhole -0.3mm", "--pinhole"},
                 {"--wavelength 550", "--wavelength"},
                 {"--source-angle 10", "--source-angle"},
                 {"--film-size 0mm", "--film-size"},
                 {"--pinhole 20mm", "--max-terms"},
                 {"--aperture polygon:2", "--aperture"},
                 {"--aperture zoneplate:0", "--aperture"},
                 {"--aperture sieve:8:2.5x", "--aperture: hole diameter 2.5x"},
                 {"--aperture mask:/nonexistent/pinhole.png", "/nonexistent/pinhole.png"}};
    for (const Case& c : cases) {
        const CommandRun r = run(std::string("psf ") + c.args + " -o " + exr.string());
        EXPECT_NE(r.status, 0) << c.args;
        EXPECT_NE(r.output.find(c.flag), std::string::npos) << c.args << ": " << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
        EXPECT_FALSE(fs::exists(exr)) << c.args;
    }
    fs::remove_all(dir);
}

TEST(SweepCommand, WritesCsvPlotAndSheetAndReportsTheOptimum) {
    const fs::path dir = temp_dir();
    const CommandRun r = run("sweep --film-distance 20mm --count 7 --resolution 41 -o " + (dir / "s").string());
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("measured optimum"), std::string::npos);
    for (const char* f : {"s.csv", "s_psfs.png", "s_spot_size.png"}) EXPECT_TRUE(fs::exists(dir / f)) << f;
    std::ifstream csv(dir / "s.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_EQ(header, "diameter_mm,diameter_over_sqrt_f_lambda,fresnel_number,r50_um,r80_um");
    int rows = 0;
    for (std::string line; std::getline(csv, line);) ++rows;
    EXPECT_EQ(rows, 7);
    fs::remove_all(dir);
}

// A CSV that cannot be moved into place (a folder of that name is in the way) is an error,
// not a "wrote": the sweep says which file, exits non-zero and leaves no temporary behind.
TEST(SweepCommand, AFailedRenameIsReportedAndLeavesNoTemporary) {
    const fs::path dir = temp_dir();
    fs::create_directories(dir / "s.csv" / "in_the_way");
    const CommandRun r = run("sweep --film-distance 20mm --count 3 --resolution 21 -o " + (dir / "s").string());
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.output.find((dir / "s.csv").string() + ": cannot move the finished file into place"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("wrote"), std::string::npos) << r.output;
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().filename(), "s.csv");
    fs::remove_all(dir);
}
