// `wavecam farm` on a real Slurm cluster: Debian's slurm-wlm and munge, started by this test on
// this one machine (tests/slurm_cluster.sh: a one-node slurm.conf in a scratch folder, free
// ports) and stopped afterwards. Labelled "host": it needs root and system daemons, and runs
// wavecam inside Slurm's programs, so the sanitizer run leaves it out.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>

#include <cstdlib>
#include <regex>

#include "command_runner.h"

namespace fs = std::filesystem;
using namespace wavecam::test;

namespace {
const std::string kWavecam = WAVECAM_BINARY;
const std::string kCluster = std::string(WAVECAM_SOURCE_DIR) + "/tests/slurm_cluster.sh";
const std::string kJob = " --method random-phase --film-distance 20mm --pinhole 0.1mm --wavelengths 3 --runs 2 "
                         "--film-subsamples 1 --seed 3 ";

class Farm : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = scratch("farm");
        auto r = run_command(kCluster + " start " + (dir_ / "cluster").string());
        start_output_ = r.output + run_command("tail -n 20 " + (dir_ / "cluster" / "*.log").string()).output;
        if (r.status != 0) return;
        setenv("SLURM_CONF", (dir_ / "cluster" / "slurm.conf").c_str(), 1);
        write_render((dir_ / "in.exr").string(), 24, 16, 2.0f, 30.0f);
        auto single = run_command(kWavecam + " apply " + path("in.exr") + " -o " + path("single.exr") + kJob);
        ASSERT_EQ(single.status, 0) << single.output;
        ready_ = true;
    }
    // A cluster that did not start fails every test (gtest would only skip them).
    void SetUp() override { ASSERT_TRUE(ready_) << "the Slurm cluster did not start:\n" << start_output_; }
    static void TearDownTestSuite() {
        run_command(kCluster + " stop " + (dir_ / "cluster").string());
        fs::remove_all(dir_);
    }
    static std::string path(const std::string& f) { return (dir_ / f).string(); }
    static fs::path dir_;
    static bool ready_;
    static std::string start_output_;
};
fs::path Farm::dir_;
bool Farm::ready_ = false;
std::string Farm::start_output_;

bool images_equal(const std::string& a, const std::string& b) {
    OIIO::ImageBuf x(a), y(b);
    if (!x.read(0, 0, true, OIIO::TypeDesc::FLOAT) || !y.read(0, 0, true, OIIO::TypeDesc::FLOAT)) return false;
    if (x.spec().width != y.spec().width || x.spec().height != y.spec().height || x.nchannels() != y.nchannels())
        return false;
    for (int j = 0; j < x.spec().height; ++j)
        for (int i = 0; i < x.spec().width; ++i)
            for (int c = 0; c < x.nchannels(); ++c)
                if (x.getchannel(i, j, 0, c) != y.getchannel(i, j, 0, c)) return false;
    return true;
}
}  // namespace

TEST_F(Farm, AFourTaskArrayEqualsTheSingleMachineImage) {
    auto r = run_command(kWavecam + " farm submit " + path("in.exr") + " -o " + path("farm.exr") + kJob +
                         " --tasks 4 --wait");
    ASSERT_EQ(r.status, 0) << r.output;
    // the estimate comes before the submission
    const size_t estimate = r.output.find("core-hours"), submitted = r.output.find("submitted array job");
    ASSERT_NE(estimate, std::string::npos) << r.output;
    EXPECT_LT(estimate, submitted) << r.output;
    EXPECT_NE(r.output.find("4 of 4 tasks"), std::string::npos) << r.output;
    EXPECT_TRUE(images_equal(path("single.exr"), path("farm.exr")));
    // each task's log has the estimate and the progress a person can read
    const std::string log = path("farm.exr.farm/logs/task-0.log");
    auto cat = run_command("cat " + log);
    EXPECT_NE(cat.output.find("terms/s measured here"), std::string::npos) << cat.output;
    auto status = run_command(kWavecam + " farm status " + path("farm.exr"));
    EXPECT_EQ(status.status, 0) << status.output;
    EXPECT_NE(status.output.find("image: merged"), std::string::npos) << status.output;
}

TEST_F(Farm, ACancelledTaskIsNamedByTheMergeAndAResubmitCompletesIt) {
    auto r = run_command(kWavecam + " farm submit " + path("in.exr") + " -o " + path("held.exr") + kJob +
                         " --tasks 4 --hold");
    ASSERT_EQ(r.status, 0) << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex("submitted array job ([0-9]+)"))) << r.output;
    const std::string job = m[1];
    // while it is queued, the same job is not submitted twice
    auto twice = run_command(kWavecam + " farm submit " + path("in.exr") + " -o " + path("held.exr") + kJob +
                             " --tasks 4");
    EXPECT_NE(twice.status, 0);
    EXPECT_NE(twice.output.find("of the last submission is still PENDING"), std::string::npos) << twice.output;
    ASSERT_EQ(run_command("scancel " + job + "_2").status, 0);  // share 3/4
    ASSERT_EQ(run_command("scontrol release " + job).status, 0);
    // wait until the array and its (now never satisfiable) merge job have left the queue
    for (int i = 0; i < 120; ++i) {
        auto q = run_command("squeue --noheader --format=%i");
        if (q.output.find_first_of("0123456789") == std::string::npos) break;
        std::system("sleep 0.5");
    }
    EXPECT_FALSE(fs::exists(path("held.exr")));
    auto status = run_command(kWavecam + " farm status " + path("held.exr"));
    EXPECT_NE(status.status, 0);
    EXPECT_NE(status.output.find("3 of 4 shares done; missing: 3 not queued"), std::string::npos) << status.output;
    auto merge = run_command(kWavecam + " merge '" + path("held.exr.farm/shares/image/share-*-of-4.exr") + "' -o " +
                             path("held.exr"));
    EXPECT_NE(merge.status, 0);
    EXPECT_NE(merge.output.find("share 3/4 missing"), std::string::npos) << merge.output;
    EXPECT_FALSE(fs::exists(path("held.exr")));

    auto again = run_command(kWavecam + " farm submit " + path("in.exr") + " -o " + path("held.exr") + kJob +
                             " --tasks 4 --wait");
    ASSERT_EQ(again.status, 0) << again.output;
    EXPECT_NE(again.output.find("1 of 4 tasks (the others are complete)"), std::string::npos) << again.output;
    EXPECT_TRUE(images_equal(path("single.exr"), path("held.exr")));
}

TEST_F(Farm, FramesGoThroughOneArrayWithAMergePerFrame) {
    write_render(path("shot.0001.exr"), 24, 16, 2.0f, 30.0f);
    write_render(path("shot.0002.exr"), 24, 16, 3.0f, 30.0f);
    auto r = run_command(kWavecam + " farm submit " + path("shot.#.exr") + " -o " + path("out.#.exr") + kJob +
                         " --tasks 2 --frames 1-2 --partition debug --wait");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("2 frames x 2 shares"), std::string::npos) << r.output;
    EXPECT_TRUE(images_equal(path("single.exr"), path("out.0001.exr")));  // frame 1 is the same render
    auto second = run_command(kWavecam + " apply " + path("shot.0002.exr") + " -o " + path("single2.exr") + kJob);
    ASSERT_EQ(second.status, 0) << second.output;
    EXPECT_TRUE(images_equal(path("single2.exr"), path("out.0002.exr")));
}

TEST_F(Farm, ConvolutionSequencesGoThroughTheArrayInFrameChunks) {
    for (int f = 1; f <= 3; ++f) {
        char name[32];
        std::snprintf(name, sizeof name, "seq.%04d.exr", f);
        write_render(path(name), 24, 16, 1.0f + f, 30.0f);
    }
    // --monochrome is a flag of farm submit as of apply, and reaches the tasks as one
    const std::string fast = " --film-distance 20mm --pinhole 0.1mm --wavelengths 3 --monochrome --no-vignetting ";
    auto r = run_command(kWavecam + " farm submit " + path("seq.#.exr") + " -o " + path("fast.#.exr") + fast +
                         " --tasks 2 --frames 1-3 --wait");
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("3 frames, convolution method"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("3 to make in 2 tasks"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("3 of 3 frames done"), std::string::npos) << r.output;
    // each frame is the image the same command makes on one machine, on one thread as the task did
    auto single = run_command(kWavecam + " apply " + path("seq.0003.exr") + " -o " + path("fast3.exr") + fast +
                              " --threads 1");
    ASSERT_EQ(single.status, 0) << single.output;
    EXPECT_TRUE(images_equal(path("fast3.exr"), path("fast.0003.exr")));
    // a re-submit finds every frame made
    auto again = run_command(kWavecam + " farm submit " + path("seq.#.exr") + " -o " + path("fast.#.exr") + fast +
                             " --tasks 2 --frames 1-3 --wait");
    EXPECT_EQ(again.status, 0) << again.output;
    EXPECT_NE(again.output.find("0 to make in 0 tasks"), std::string::npos) << again.output;
}

TEST_F(Farm, BadSubmissionsAndStatusWithoutAJob) {
    auto none = run_command(kWavecam + " farm status " + path("nothing.exr"));
    EXPECT_NE(none.status, 0);
    EXPECT_NE(none.output.find("no farm job here"), std::string::npos) << none.output;
    auto tasks = run_command(kWavecam + " farm submit " + path("in.exr") + " -o " + path("x.exr") + kJob + " --tasks 0");
    EXPECT_NE(tasks.output.find("--tasks: expected at least 1"), std::string::npos) << tasks.output;
    auto many = run_command(kWavecam + " farm submit " + path("in.exr") + " -o " + path("x.exr") + kJob +
                            " --tasks 100000");
    EXPECT_NE(many.output.find("more than the job's 6 units x 16 film rows"), std::string::npos) << many.output;
    auto frames = run_command(kWavecam + " farm submit " + path("in.exr") + " -o " + path("x.exr") + kJob +
                              " --tasks 2 --frames 1-2");
    EXPECT_NE(frames.output.find("has no frame number pattern"), std::string::npos) << frames.output;
    auto bound = run_command(kWavecam + " farm submit " + path("in.exr") + " -o " + path("x.exr") + kJob +
                             " --tasks 2 --max-terms 1e6");
    EXPECT_NE(bound.output.find("beyond --max-terms; use more --tasks"), std::string::npos) << bound.output;
    EXPECT_FALSE(fs::exists(path("x.exr.farm")));
}
