// `wavecam apply` against a hostile tester (issue 26): inputs and settings that aborted the
// program, hung it, or lost the user's file. Each now gets exit 1 or 2 and one line of ours,
// within seconds, with no output and no temporary left; signals exit 130/143; a full disk keeps
// the old output.
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <limits.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>

#include <OpenImageIO/imageio.h>

#include "command_runner.h"

namespace fs = std::filesystem;
using namespace wavecam::test;

namespace {
const std::string kWavecam = WAVECAM_BINARY;

std::string file_bytes(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), {}};
}

struct Timed {
    CommandRun run;
    double seconds;
    int exit_code() const { return WIFEXITED(run.status) ? WEXITSTATUS(run.status) : -1; }
};

// Runs the command with a hard stop (KILL after `limit` s: a hang then fails the test instead of
// stalling the suite).
Timed timed(const std::string& cmd, int limit = 30) {
    const auto start = std::chrono::steady_clock::now();
    CommandRun r = run_command("timeout -s KILL " + std::to_string(limit) + " " + cmd);
    return {r, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()};
}

// No hidden temporary (".NAME.tmpPID.ext", ".wavecam.tmpPID.ext") left in `dir`.
void expect_no_temporary(const fs::path& dir) {
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}
}  // namespace

// Each of these ended in `terminate called ...` (SIGABRT) or ran on without a word.
TEST(ApplyHostile, AbortsAndHangsBecomeOneLineBeforeTheWork) {
    const fs::path dir = scratch("hostile_refused");
    auto render = [&](const std::string& name, int w, int h, float z, float fov) {
        write_render((dir / name).string(), w, h, z, fov);
        return (dir / name).string();
    };
    const std::string good = render("good.exr", 16, 16, 2.0f, 30.0f);
    const std::string fifo = (dir / "fifo.exr").string();
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    fs::create_directories(dir / "folder.exr");
    {  // a header that claims 20000 x 20000 pixels in a file of under a megabyte (no pixels)
        OIIO::ImageSpec spec(20000, 20000, 4, OIIO::TypeDesc::HALF);
        spec.channelnames = {"R", "G", "B", "Z"};
        spec.tile_width = spec.tile_height = 64;
        auto forged = OIIO::ImageOutput::create((dir / "forged.exr").string());
        ASSERT_TRUE(forged && forged->open((dir / "forged.exr").string(), spec));
        forged->close();
    }
    const std::string long_name(300, 'n');
    std::string deep_path = dir.string();
    while (deep_path.size() <= PATH_MAX) deep_path += "/" + std::string(200, 'd');
    struct Case {
        std::string input, extra, expect;
    } cases[] = {
        // aborts: std::bad_alloc after 28 s (its vertical field is 173 degrees wide)
        {render("narrow.exr", 2, 128, 2.0f, 30.0f), "",
         "narrow.exr: a field of view of 30 degrees (from the file's wavecam.fov attribute) puts the 2x128 frame's "
         "corners 86.6"},
        // std::length_error: a subnormal or tiny depth
        {render("subnormal.exr", 16, 16, 1e-40f, 30.0f), "",
         "channel 'Z' at pixel (0, 0) is 9.99995e-41, nearer than a pinhole of 0.315079mm can image; expected a "
         "distance of 0.00315079 m or more (10 pinhole diameters), or inf for sky"},
        {render("tiny_depth.exr", 16, 16, 1e-30f, 30.0f), "", "is 1e-30, nearer than a pinhole"},
        {good, "--pinhole 1000m",
         "good.exr: a pinhole of 1e+06mm is wider than the film (26.7949mm across at a film distance of 50mm and a "
         "field of view of 30 degrees); expected a pinhole from 681.25nm to 26.7949mm (--pinhole)"},
        {good, "-o " + (dir / (long_name + ".exr")).string(),
         "cannot write: a file or folder name of 304 characters, beyond the file system's limit of 255 (NAME_MAX)"},
        {good, "-o " + deep_path + "/out.exr", "(PATH_MAX 4096, less room for the temporary beside it)"},
        {(dir / (long_name + ".exr")).string(), "",
         "cannot be read as an image (a file or folder name of 304 characters, beyond the file system's limit of 255 "
         "(NAME_MAX))"},
        {deep_path + "/in.exr", "", "cannot be read as an image (a path of"},
        {(dir / "forged.exr").string(), "--max-memory 1GiB",
         "forged.exr: 20000x20000 pixels x 4 channels need about 6103.52 MiB to read, beyond the max-memory limit of "
         "1024 MiB"},
        // hangs: no message, no progress, signals ignored
        {render("fov_zero.exr", 16, 16, 2.0f, 1e-30f), "",
         "a field of view of 1e-30 degrees (from the file's wavecam.fov attribute) is too narrow to image; expected "
         "0.01 to 151.996 degrees across this frame (corners within 80 degrees of the axis) (--fov)"},
        {render("fov_180.exr", 16, 16, 2.0f, 179.999f), "", "frame's corners 89.9996 degrees off axis"},
        {good, "--fov 170deg", "a field of view of 170 degrees (from --fov) puts the 16x16 frame's corners"},
        {good, "--pinhole 1nm",
         "a pinhole of 1e-06mm is smaller than the wavelength of 681.25nm; expected a pinhole from 681.25nm"},
        {good, "--pinhole 0.5um --wavelengths 550nm", "smaller than the wavelength of 550nm"},
        {good, "--film-distance 1nm --pinhole 0.3mm", "a pinhole of 0.3mm is wider than the film"},
        {render("near.exr", 16, 16, 1e-6f, 30.0f), "", "channel 'Z' at pixel (0, 0) is 1e-06, nearer than"},
        // the fast path's estimate counts each thread's PSF working memory (a 0.7 um pinhole's
        // PSF spans the frame: ~200 MiB a thread), before any of it is allocated
        {good, "--pinhole 0.7um --max-memory 100MiB", "good.exr: 16x16 pixels need about "},
        // found by fuzz_job: a NaN estimate passed the limits (std::length_error)
        {good, "--wavelengths 1e-40nm", "--wavelengths: expected wavelengths from 100nm to 10um, got '1e-40nm'"},
        {"/dev/zero", "", "/dev/zero: cannot be read as an image (a character device; expected an image file)"},
        {"/dev/urandom", "", "/dev/urandom: cannot be read as an image (a character device"},
        {fifo, "", "fifo.exr: cannot be read as an image (a named pipe (FIFO); expected an image file)"},
        {(dir / "folder.exr").string(), "", "folder.exr: cannot be read as an image (a folder; expected an image file)"},
        {good, "--aperture mask:" + fifo, "fifo.exr: cannot be read as an image (a named pipe"},
    };
    const fs::path out = dir / "out.exr";
    for (const Case& c : cases) {
        const std::string output = c.extra.rfind("-o ", 0) == 0 ? "" : " -o " + out.string();
        const Timed r = timed(kWavecam + " apply " + c.input + output + " " + c.extra);
        const std::string what = c.input.substr(0, 80) + " " + c.extra.substr(0, 80);
        EXPECT_TRUE(r.exit_code() == 1 || r.exit_code() == 2) << what << ": status " << r.run.status << "\n"
                                                              << r.run.output;
        EXPECT_NE(r.run.output.find(c.expect), std::string::npos) << what << ":\n" << r.run.output;
        EXPECT_EQ(r.run.output.find("terminate called"), std::string::npos) << what;
        EXPECT_LT(r.seconds, 10.0) << what;
        EXPECT_FALSE(fs::exists(out)) << what;
    }
    expect_no_temporary(dir);
    // found by fuzz_job: a film distance of 1e6 m spun forever choosing an FFT size; now a
    // (pointless but valid) camera that finishes at once
    const Timed far = timed(kWavecam + " apply " + good + " -o " + out.string() + " --film-distance 1e6m --pinhole 1mm");
    EXPECT_EQ(far.exit_code(), 0) << far.run.output;
    EXPECT_LT(far.seconds, 10.0);
    fs::remove(out);
    // the longest name a file system takes is still written (its temporary gets a short name)
    const fs::path longest = dir / (std::string(251, 'x') + ".exr");
    const Timed w = timed(kWavecam + " apply " + good + " -o " + longest.string());
    EXPECT_EQ(w.exit_code(), 0) << w.run.output;
    EXPECT_TRUE(fs::exists(longest));
    expect_no_temporary(dir);
    fs::remove_all(dir);
}

// SIGINT and SIGTERM mid-run: the exact sums stop through their progress callback, a fast-path
// PSF that takes seconds by the watchdog; either way 130 or 143, the old output untouched, no
// temporary.
TEST(ApplyHostile, SignalsExit130Or143AndWriteNothing) {
    const fs::path dir = scratch("hostile_signals");
    write_render((dir / "in.exr").string(), 64, 64, 2.0f, 30.0f);
    write_render((dir / "wide.exr").string(), 16, 16, 2.0f, 150.0f);
    const fs::path out = dir / "out.exr";
    std::ofstream(out) << "the user's old output";
    const std::string before = file_bytes(out);
    const std::string runs[] = {
        (dir / "in.exr").string() + " --method exact --runs 20 --wavelengths 16 --film-subsamples 3",
        (dir / "wide.exr").string(),  // fast path, corners 79 degrees off axis: ~30 s of PSFs
    };
    for (const std::string& run : runs)
        for (const auto& [signal, status] : {std::pair<std::string, int>{"INT", 130}, {"TERM", 143}}) {
            const Timed r = timed("timeout --preserve-status -s " + signal + " 2 " + kWavecam + " apply " + run +
                                  " -o " + out.string());
            EXPECT_EQ(r.exit_code(), status) << signal << " " << run << ":\n" << r.run.output;
            EXPECT_NE(r.run.output.find("interrupted"), std::string::npos) << signal << ": " << r.run.output;
            EXPECT_LT(r.seconds, 4.5) << signal << " " << run << ": stopped " << r.seconds - 2 << " s after it";
            EXPECT_EQ(file_bytes(out), before) << signal << " " << run;
        }
    expect_no_temporary(dir);
    fs::remove_all(dir);
}

// A full disk: the run fails, the old output stays byte for byte, no temporary is left.
// Needs root (mount a 64 KiB tmpfs); skipped with a message otherwise.
TEST(ApplyHostile, FullDiskKeepsTheOldOutput) {
    const fs::path dir = scratch("hostile_full");
    const fs::path disk = dir / "disk";
    fs::create_directories(disk);
    if (::mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=64k") != 0) {
        fs::remove_all(dir);
        GTEST_SKIP() << "cannot mount a small tmpfs here (needs root): " << std::strerror(errno);
    }
    write_render((dir / "in.exr").string(), 64, 64, 2.0f, 30.0f);
    write_render((dir / "small.exr").string(), 8, 8, 2.0f, 30.0f);
    for (const char* name : {"out.exr", "out.png"}) std::ofstream(disk / name) << "the user's old " << name;
    {  // fill what is left
        std::ofstream filler(disk / "filler", std::ios::binary);
        const std::string block(4096, 'f');
        for (int k = 0; k < 64 && filler; ++k) filler.write(block.data(), block.size());
    }
    for (const char* name : {"out.exr", "out.png"}) {
        const std::string before = file_bytes(disk / name);
        const Timed r = timed(kWavecam + " apply " + (dir / "in.exr").string() + " -o " + (disk / name).string());
        EXPECT_EQ(r.exit_code(), 1) << name << ":\n" << r.run.output;
        EXPECT_NE(r.run.output.find(std::string(name) + ": cannot write: "), std::string::npos) << r.run.output;
        EXPECT_NE(r.run.output.find("the disk is full"), std::string::npos) << r.run.output;
        EXPECT_EQ(file_bytes(disk / name), before) << name;
    }
    expect_no_temporary(disk);
    // with room again, the same runs replace the outputs
    fs::remove(disk / "filler");
    for (const char* name : {"out.exr", "out.png"}) {
        const Timed r = timed(kWavecam + " apply " + (dir / "small.exr").string() + " -o " + (disk / name).string());
        EXPECT_EQ(r.exit_code(), 0) << name << ":\n" << r.run.output;
        EXPECT_NE(file_bytes(disk / name).substr(0, 10), "the user's") << name;
    }
    expect_no_temporary(disk);
    EXPECT_EQ(::umount(disk.c_str()), 0) << std::strerror(errno);
    fs::remove_all(dir);
}
