// `wavecam apply` against a hostile tester: inputs and settings that aborted the
// program, hung it, or lost the user's file. Each now gets exit 1 or 2 and one line of ours,
// within seconds, with no output and no temporary left; signals exit 130/143; a full disk keeps
// the old output.
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <limits.h>

#include <cerrno>
#include <csignal>
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
        {good, "--film-distance 1nm --pinhole 0.3mm", "--film-distance: expected a film distance of 0.1mm or more"},
        {good, "--film-distance 0.1mm --pinhole 0.3mm", "a pinhole of 0.3mm is wider than the film"},
        {render("near.exr", 16, 16, 1e-6f, 30.0f), "", "channel 'Z' at pixel (0, 0) is 1e-06, nearer than"},
        // the convolution method's estimate counts its plan's working memory before any of it is
        // allocated (a 0.7 um pinhole's PSF spans the frame: its grid in direction cosines, its
        // on-axis PSFs' working memory, about 17 MiB for a 16 x 16 frame)
        {good, "--pinhole 0.7um --max-memory 8MiB", "good.exr: 16x16 pixels need about "},
        // the kernel summation's estimate counts its kernels' spectra (hundreds of MiB at 1080p), before
        // any of them is computed
        {good, "--method random-phase --summation kernel --max-memory 3MiB", "MiB of them the kernel summation's kernels)"},
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

// SIGINT and SIGTERM mid-run: the point sums stop through their progress callback, a fast-path
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
        (dir / "in.exr").string() + " --method random-phase --runs 20 --wavelengths 16 --film-subsamples 3",
        (dir / "wide.exr").string(),  // convolution method, corners 79 degrees off axis: ~30 s of PSFs
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

namespace {
// True once a hidden temporary (".out.exr.tmpPID.exr") is in `dir`.
bool temporary_present(const fs::path& dir) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
        if (e.path().filename().string().find(".tmp") != std::string::npos) return true;
    return false;
}

// What one `apply_while_writing` saw.
struct WriteRun {
    int status = 0;          // the exit status; -1: killed by a signal, not exited
    double writing = 0;      // how long the temporary was there (in a run without a signal)
    bool signalled = false;  // the signal was sent while the temporary was there
};

// Runs `wavecam apply input -o output` (output silenced); when `sig` > 0, sends it `delay` after
// the temporary appears, but only while the temporary is still there: the process is stopped
// (SIGSTOP) while the test looks, so a write that has already ended is not mistaken for one that
// a signal interrupted.
WriteRun apply_while_writing(const fs::path& input, const fs::path& output, int sig, std::chrono::microseconds delay) {
    using Clock = std::chrono::steady_clock;
    const pid_t pid = ::fork();
    if (pid == 0) {
        std::freopen("/dev/null", "w", stdout);
        std::freopen("/dev/null", "w", stderr);
        ::execl(kWavecam.c_str(), kWavecam.c_str(), "apply", input.c_str(), "-o", output.c_str(), "--wavelengths",
                "3", "--threads", "2", static_cast<char*>(nullptr));
        ::_exit(127);
    }
    const fs::path dir = output.parent_path();
    const auto limit = Clock::now() + std::chrono::seconds(60);
    WriteRun run;
    int status = 0;
    bool tried = false, seen = false, ended = false;
    Clock::time_point appeared{}, gone{};
    while (!ended && ::waitpid(pid, &status, WNOHANG) == 0) {
        if (Clock::now() > limit) ::kill(pid, SIGKILL);
        if (!seen && temporary_present(dir)) {
            seen = true;
            appeared = Clock::now();
        }
        if (seen && gone == Clock::time_point{} && !temporary_present(dir)) gone = Clock::now();
        if (seen && sig > 0 && !tried && Clock::now() - appeared >= delay) {
            tried = true;
            ::kill(pid, SIGSTOP);
            int stopped = 0;
            ::waitpid(pid, &stopped, WUNTRACED);
            if (!WIFSTOPPED(stopped)) {  // it ended before it could be stopped
                status = stopped;
                ended = true;
                break;
            }
            run.signalled = temporary_present(dir);
            if (run.signalled) ::kill(pid, sig);
            ::kill(pid, SIGCONT);
        }
        ::usleep(500);
    }
    if (seen && gone == Clock::time_point{}) gone = Clock::now();
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.writing = std::chrono::duration<double>(gone - appeared).count();
    return run;
}
}  // namespace

// Every catchable terminating signal sent while the output is being written (a 512 x 512
// frame of noise, which compresses slowly: its temporary lives about a tenth of a second), each
// at two of four delays into the write: exit 128 + N, the old output byte for byte, no temporary.
TEST(ApplyHostile, EveryTerminatingSignalDuringTheWriteKeepsTheOldOutput) {
    const fs::path dir = scratch("hostile_signal_write");
    const fs::path input = dir / "noise.exr", out_dir = dir / "out", out = out_dir / "out.exr";
    fs::create_directories(out_dir);
    {
        OIIO::ImageSpec spec(512, 512, 4, OIIO::TypeDesc::FLOAT);
        spec.channelnames = {"R", "G", "B", "Z"};
        spec.attribute("wavecam.fov", 40.0f);
        std::vector<float> px(spec.image_pixels() * 4);
        uint32_t state = 12345;
        for (size_t k = 0; k < px.size(); ++k) {
            state = state * 1664525u + 1013904223u;
            px[k] = k % 4 == 3 ? 3.0f : float(state >> 8) / float(1 << 24);
        }
        auto o = OIIO::ImageOutput::create(input.string());
        ASSERT_TRUE(o && o->open(input.string(), spec) && o->write_image(OIIO::TypeDesc::FLOAT, px.data()) && o->close());
    }
    // how long the write takes here, without a signal
    const WriteRun plain = apply_while_writing(input, out, 0, {});
    const double writing = plain.writing;
    ASSERT_EQ(plain.status, 0);
    ASSERT_GT(writing, 0.02) << "the write must take measurable time for this test";
    std::ofstream(out, std::ios::trunc) << "the user's old output";
    const std::string before = file_bytes(out);
    const int signals[] = {SIGHUP, SIGPIPE, SIGXCPU, SIGXFSZ, SIGUSR1, SIGUSR2, SIGINT, SIGTERM};
    for (int k = 0; k < 8; ++k)
        for (const double at : {0.25 * (k % 4), 0.25 * ((k + 2) % 4)}) {  // 0 to 3/4 of the write
            const int sig = signals[k];
            // a write that ended sooner than the first one did is tried again with half the delay
            WriteRun run;
            double part = at;
            for (int attempt = 0; attempt < 6 && !run.signalled; ++attempt, part /= 2) {
                const auto delay = std::chrono::microseconds(long(part * writing * 1e6));
                run = apply_while_writing(input, out, sig, delay);
                if (!run.signalled) std::ofstream(out, std::ios::trunc) << "the user's old output";  // it wrote
            }
            ASSERT_TRUE(run.signalled) << strsignal(sig) << ": never sent while the temporary was there";
            const int status = run.status;
            EXPECT_EQ(status, 128 + sig) << strsignal(sig) << " at " << at << " of the write";
            EXPECT_EQ(file_bytes(out), before) << strsignal(sig) << " at " << at << " of the write";
            EXPECT_FALSE(temporary_present(out_dir)) << strsignal(sig) << " at " << at << " of the write";
        }
    fs::remove_all(dir);
}

// Bounds before allocation and messages of ours: each row exits 2 within seconds, in our words,
// naming the setting at fault and what it expects, with nothing written.
TEST(ApplyHostile, BoundsAndMessagesNameTheSettingAndWhatItExpects) {
    const fs::path dir = scratch("hostile_messages");
    const std::string in = (dir / "in.exr").string(), out = (dir / "out.exr").string();
    write_render(in, 8, 6, 2.0f, 30.0f);
    const std::string apply = kWavecam + " apply " + in + " -o " + out;
    const std::string psf = kWavecam + " psf -o " + out;
    const struct {
        std::string command, message;
    } rows[] = {
        {apply + " --frames 1-100000000", "--frames: '1-100000000' is more than 100000 frames"},
        {apply + " --frames 1-99999,1-10", "--frames: '1-99999,1-10' is more than 100000 frames"},
        {apply + " --frames one-two", "--frames: expected a frame range such as 1-100"},
        {psf + " --max-terms nan", "--max-terms: expected a number of terms > 0 such as 4e12 (not inf or nan), got 'nan'"},
        {psf + " --max-terms inf", "--max-terms: expected a number of terms > 0"},
        {apply + " --max-terms nan", "--max-terms: expected a number of terms > 0 such as 4e12 (not inf or nan)"},
        {apply + " --max-terms -inf", "--max-terms: expected a number of terms > 0"},
        {apply + " --pinhole 0.3 mm", "--pinhole 0.3 mm: a unit must follow its number without a space, e.g. --pinhole 0.3mm"},
        {psf + " --wavelength 550 nm", "--wavelength 550 nm: a unit must follow its number without a space"},
        {apply + " --wavelengths 1e9", "--wavelengths: expected a count 1-1000 or a list such as 450nm,550nm,650nm, got '1e9'"},
        {apply + " --wavelengths -3", "--wavelengths: expected a count 1-1000 or a list such as 450nm,550nm,650nm, got '-3'"},
        {apply + " --wavelengths 1001", "--wavelengths: expected a count 1-1000 or a list"},
        {apply + " --threads 100000", "--threads: expected 0 (every core) to 1024 threads, got '100000'"},
        {psf + " --threads 100000", "--threads: expected 0 (every core) to 1024 threads, got '100000'"},
        {apply + " --threads abc", "--threads: expected a whole number, got 'abc'"},
        {apply + " --film-distance 1nm", "--film-distance: expected a film distance of 0.1mm or more, got '1nm'"},
        {psf + " --film-distance 1nm", "--film-distance: expected a film distance of 0.1mm or more, got '1nm'"},
        {kWavecam + " sweep --film-distance 1nm -o " + (dir / "s").string(), "--film-distance: expected a film distance"},
        {apply + " --pinhole", "--pinhole: expected a value after it"},
        {apply + " --aperture sieve:100000", "--aperture sieve:100000:1.5x:50%:1: about 2.63e+11 pinhole samples per PSF need"},
        {kWavecam + " apply " + in, "-o,--output is required"},
        {apply + " stray", "'stray' was not expected"},
        // an option given twice is refused, whichever option, in every command
        {apply + " --pinhole 0.3mm --pinhole 0.2mm", "--pinhole given twice; give each option once"},
        {apply + " --runs=2 --runs 3", "--runs given twice"},
        {apply + " --monochrome --monochrome", "--monochrome given twice"},
        {apply + " --no-jitter --no-jitter", "--no-jitter given twice"},
        {apply + " --output " + out, "-o (--output) given twice"},
        {apply + " --threads 1 --threads 2", "--threads given twice"},
        {psf + " --pinhole 0.3mm --pinhole 0.2mm", "wavecam psf: --pinhole given twice"},
        {kWavecam + " merge a.exr -o m.exr -o n.exr", "wavecam merge: -o given twice"},
        {kWavecam + " sweep --count 5 --count 6", "wavecam sweep: --count given twice"},
        {kWavecam + " farm submit " + in + " -o " + out + " --tasks 2 --tasks 3", "wavecam farm submit: --tasks given twice"},
    };
    for (const auto& row : rows) {
        const Timed r = timed(row.command);
        EXPECT_EQ(r.exit_code(), 2) << row.command << ":\n" << r.run.output;
        EXPECT_NE(r.run.output.find(row.message), std::string::npos) << row.command << ":\n" << r.run.output;
        EXPECT_EQ(r.run.output.find("Run with --help"), std::string::npos) << r.run.output;  // CLI11's words
        EXPECT_LT(r.seconds, 10) << row.command;
        EXPECT_FALSE(fs::exists(out)) << row.command;
    }
    fs::remove_all(dir);
}

// A file that cannot be read says so, with the reason (not "is not an OpenEXR file"); as root,
// the run is made as nobody, for whom the file is unreadable.
TEST(ApplyHostile, UnreadableFileSaysItCannotBeRead) {
    const fs::path dir = scratch("hostile_unreadable");
    fs::permissions(dir, fs::perms::all);
    const std::string in = (dir / "in.exr").string();
    write_render(in, 8, 6, 2.0f, 30.0f);
    fs::permissions(in, fs::perms::none);
    std::string as = "";
    if (::geteuid() == 0) {
        if (run_command("command -v setpriv").status != 0) GTEST_SKIP() << "root, and no setpriv to run as nobody";
        as = "setpriv --reuid=nobody --regid=nogroup --clear-groups ";
    }
    const Timed r = timed(as + kWavecam + " apply " + in + " -o " + (dir / "out.exr").string());
    if (r.run.output.find("Permission denied") == std::string::npos && r.exit_code() == 126)
        GTEST_SKIP() << "nobody cannot run the build here: " << r.run.output;
    EXPECT_EQ(r.exit_code(), 2) << r.run.output;
    EXPECT_NE(r.run.output.find(in + ": cannot be read as an image (Permission denied)"), std::string::npos)
        << r.run.output;
    EXPECT_EQ(r.run.output.find("OpenEXR"), std::string::npos) << r.run.output;
    fs::remove_all(dir);
}

// A sequence that fails at frame 3 of 5 names the frames done, the one that failed, and those
// not tried.
TEST(ApplyHostile, FailingSequenceNamesFramesDoneFailedAndNotTried) {
    const fs::path dir = scratch("hostile_sequence");
    for (int f : {1, 2, 4, 5})
        write_render((dir / ("shot." + std::to_string(f) + ".exr")).string(), 8, 6, 2.0f, 30.0f);
    const Timed r = timed(kWavecam + " apply " + (dir / "shot.@.exr").string() + " -o " +
                          (dir / "out.@.exr").string() + " --frames 1-5 --wavelengths 3");
    EXPECT_EQ(r.exit_code(), 2) << r.run.output;
    EXPECT_NE(r.run.output.find("shot.3.exr"), std::string::npos) << r.run.output;
    EXPECT_NE(r.run.output.find("frames done: 1-2; failed: 3; not tried: 4-5"), std::string::npos) << r.run.output;
    EXPECT_TRUE(fs::exists(dir / "out.2.exr"));
    EXPECT_FALSE(fs::exists(dir / "out.4.exr"));
    fs::remove_all(dir);
}
