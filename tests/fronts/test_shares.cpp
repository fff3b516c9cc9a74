// Shares and merge (`wavecam apply --share K/N`, `wavecam merge`) as a user runs them: the
// merged image equals the single-machine run, and every bad set is refused with nothing written.
#include <gtest/gtest.h>
#include <OpenImageIO/imagebuf.h>

#include <fstream>
#include <set>
#include <sstream>

#include "command_runner.h"
#include "wavecam/atomic_write.h"
#include "wavecam/diffract_image.h"
#include "wavecam/share_files.h"
#include "wavecam/work_share.h"
#include "summation_flag.h"

namespace fs = std::filesystem;
using namespace wavecam::test;

namespace {
const std::string kWavecam = WAVECAM_BINARY;
// tiny: 24 x 16 pixels, 3 wavelengths, 2 runs, one film point per pixel
const std::string kJob = " --method random-phase --film-distance 20mm --pinhole 0.1mm --wavelengths 3 --runs 2 "
                         "--film-subsamples 1 --seed 7 ";
// kJob through the evaluator this run of the tests asks for (summation_flag.h)
std::string job() { return kJob + test_summation_flag() + " "; }

// kJob with `extra`'s settings in place of its own (each option is given once).
std::string job_with(const std::string& extra) {
    std::istringstream words(kJob + test_summation_flag());
    std::string job, key, value;
    while (words >> key >> value)
        if (extra.find(key + " ") == std::string::npos && extra.find(key + "=") == std::string::npos)
            job += " " + key + " " + value;
    return job + " " + extra + " ";
}

struct Fixture {
    fs::path dir;
    std::string input;
    explicit Fixture(const std::string& name) : dir(scratch(name)), input((dir / "in.exr").string()) {
        write_render(input, 24, 16, 2.0f, 30.0f);
        // saturated primaries: their spectra go negative at some wavelengths, so share files
        // carry the negative channels too
        OIIO::ImageBuf in(input);
        in.read(0, 0, true, OIIO::TypeDesc::FLOAT);
        for (int j = 10; j < 14; ++j) {
            in.setpixel(2, j, std::vector<float>{1, 0, 0, 2}.data());
            in.setpixel(12, j, std::vector<float>{0, 0, 1, 2}.data());
            in.setpixel(20, j, std::vector<float>{0, 1, 0, 2}.data());
        }
        in.write(input);
    }
    ~Fixture() { fs::remove_all(dir); }
    std::string path(const std::string& f) const { return (dir / f).string(); }
    // `flag` "--part" gives the share with the flag's other spelling
    CommandRun share(int k, int n, const std::string& out, const std::string& extra = "",
                     const std::string& flag = "--share") const {
        return run_command(kWavecam + " apply " + input + " -o " + path(out) + job_with(extra) + " " + flag + " " +
                           std::to_string(k) + "/" + std::to_string(n));
    }
    CommandRun merge(const std::string& shares, const std::string& out) const {
        return run_command("cd " + dir.string() + " && " + kWavecam + " merge " + shares + " -o " + path(out));
    }
};

// Largest |a - b| over every channel; both images must have the same size and channels.
float max_difference(const std::string& a, const std::string& b) {
    OIIO::ImageBuf x(a), y(b);
    EXPECT_TRUE(x.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << a;
    EXPECT_TRUE(y.read(0, 0, true, OIIO::TypeDesc::FLOAT)) << b;
    EXPECT_EQ(x.spec().width, y.spec().width);
    EXPECT_EQ(x.spec().height, y.spec().height);
    EXPECT_EQ(x.spec().channelnames, y.spec().channelnames);
    float worst = 0;
    for (int j = 0; j < x.spec().height; ++j)
        for (int i = 0; i < x.spec().width; ++i)
            for (int c = 0; c < x.nchannels(); ++c) worst = std::max(worst, std::abs(x.getchannel(i, j, 0, c) -
                                                                                       y.getchannel(i, j, 0, c)));
    return worst;
}
}  // namespace

// Every (unit, row) of the job lies in exactly one share, for any N up to units x rows.
TEST(WorkShare, EveryUnitRowInExactlyOneShare) {
    for (int units_w : {1, 3}) {
        for (int runs : {1, 2, 5}) {
            const int height = 7, units = units_w * runs;
            for (int n = 1; n <= units * height; ++n) {
                std::vector<int> cover(units * height, 0);
                for (int k = 1; k <= n; ++k) {
                    auto s = wavecam::work_share(k, n, units_w, runs, height);
                    ASSERT_TRUE(s.ok()) << s.error;
                    ASSERT_LT(s.value.unit_begin, s.value.unit_end);
                    ASSERT_LT(s.value.row_begin, s.value.row_end);
                    for (int u = s.value.unit_begin; u < s.value.unit_end; ++u)
                        for (int r = s.value.row_begin; r < s.value.row_end; ++r) ++cover[u * height + r];
                }
                for (int c : cover) ASSERT_EQ(c, 1) << "units " << units << " n " << n;
            }
            EXPECT_FALSE(wavecam::work_share(1, units * height + 1, units_w, runs, height).ok());
        }
    }
    EXPECT_FALSE(wavecam::parse_share("0/4").ok());
    EXPECT_FALSE(wavecam::parse_share("5/4").ok());
    EXPECT_FALSE(wavecam::parse_share("2of4").ok());
    EXPECT_TRUE(wavecam::parse_share("2/4").ok());
}

// Shares of whole units (4 of 6) and bands of rows (13 > 6 units) merge into the single run's image.
TEST(Shares, MergeEqualsTheSingleMachineRun) {
    Fixture f("shares_equal");
    auto single = run_command(kWavecam + " apply " + f.input + " -o " + f.path("single.exr") + job());
    ASSERT_EQ(single.status, 0) << single.output;
    for (int n : {4, 13}) {
        for (int k = 1; k <= n; ++k) {
            auto r = f.share(k, n, "n" + std::to_string(n) + "_share" + std::to_string(k) + ".exr");
            ASSERT_EQ(r.status, 0) << r.output;
        }
        OIIO::ImageBuf last(f.path("n" + std::to_string(n) + "_share" + std::to_string(n) + ".exr"));
        ASSERT_TRUE(last.read());
        EXPECT_GE(last.spec().channelindex("w002.r001.neg"), 0) << "the test should cover negative power";
        const std::string out = "merged" + std::to_string(n) + ".exr";
        auto m = f.merge("'n" + std::to_string(n) + "_share*.exr'", out);
        ASSERT_EQ(m.status, 0) << m.output;
        // the same sums in the same order: bit for bit on one machine
        EXPECT_EQ(max_difference(f.path("single.exr"), f.path(out)), 0.0f) << n << " shares";
    }
    // the image is not trivially equal to its input or to zero
    EXPECT_GT(max_difference(f.path("single.exr"), f.input), 1e-3f);
}

// An input rendered with overscan: the share files hold the input's rows (the margin's film is not
// summed), and the merge crops the margin as the single run does.
TEST(Shares, OverscanSharesMergeEqualToTheSingleRun) {
    Fixture f("shares_overscan");
    const std::string overscan = " --overscan 3";
    auto single = run_command(kWavecam + " apply " + f.input + " -o " + f.path("single.exr") + job_with(overscan));
    ASSERT_EQ(single.status, 0) << single.output;
    for (int k = 1; k <= 3; ++k) {
        auto r = f.share(k, 3, "share" + std::to_string(k) + ".exr", overscan);
        ASSERT_EQ(r.status, 0) << r.output;
    }
    auto m = f.merge("'share*.exr'", "merged.exr");
    ASSERT_EQ(m.status, 0) << m.output;
    OIIO::ImageBuf merged(f.path("merged.exr"));
    ASSERT_TRUE(merged.read());
    EXPECT_EQ(merged.spec().width, 24 - 2 * 3);
    EXPECT_EQ(merged.spec().height, 16 - 2 * 3);
    EXPECT_EQ(max_difference(f.path("single.exr"), f.path("merged.exr")), 0.0f);
}

TEST(Shares, BadSetsAreRefusedNamingTheShareAndNothingIsWritten) {
    Fixture f("shares_bad");
    for (int k = 1; k <= 3; ++k) ASSERT_EQ(f.share(k, 3, "p" + std::to_string(k) + ".exr").status, 0);
    // other seed, other setting, other input: share 2 made differently
    ASSERT_EQ(f.share(2, 3, "seed2.exr", " --seed 8").status, 0);
    ASSERT_EQ(f.share(2, 3, "pinhole2.exr", " --pinhole 0.12mm").status, 0);
    write_render(f.path("other.exr"), 24, 16, 3.0f, 30.0f);
    ASSERT_EQ(run_command(kWavecam + " apply " + f.path("other.exr") + " -o " + f.path("input2.exr") + job() +
                          " --share 2/3")
                  .status,
              0);
    ASSERT_EQ(f.share(2, 4, "split2.exr").status, 0);
    fs::copy_file(f.path("p2.exr"), f.path("copy2.exr"));
    {  // corrupt: the file cut short, and one pixel changed behind the checksum's back
        std::string bytes;
        {
            std::ifstream in(f.path("p2.exr"), std::ios::binary);
            bytes.assign(std::istreambuf_iterator<char>(in), {});
        }
        std::ofstream(f.path("cut2.exr"), std::ios::binary) << bytes.substr(0, bytes.size() * 2 / 3);
        OIIO::ImageBuf p(f.path("p2.exr"));
        ASSERT_TRUE(p.read(0, 0, true, OIIO::TypeDesc::FLOAT));
        p.setpixel(3, 4, std::vector<float>(p.nchannels(), 0.5f).data());
        ASSERT_TRUE(p.write(f.path("edited2.exr")));
    }
    std::ofstream(f.path("text.exr")) << "not an image";
    {  // decided otherwise: share 2 as another device would have made it
        OIIO::ImageBuf p(f.path("p2.exr"));
        ASSERT_TRUE(p.read(0, 0, true, OIIO::TypeDesc::FLOAT));
        const std::string decided = p.spec().get_string_attribute("wavecam.share.decision");
        // kernel, or each wavelength's two sums ("550nm nufft/direct"), and the device
        EXPECT_TRUE(decided == "kernel on cpu" || decided.find("nm ") != std::string::npos) << decided;
        EXPECT_NE(decided.find(" on cpu"), std::string::npos) << decided;
        p.specmod().attribute("wavecam.share.decision", "550nm direct/direct on gpu");
        ASSERT_TRUE(p.write(f.path("decided2.exr")));
    }

    struct Case {
        std::string shares, expected;
    };
    const std::vector<Case> cases = {
        {"p1.exr p3.exr", "share 2/3 missing (given: 2 of 3)"},
        {"p1.exr p2.exr copy2.exr p3.exr", "share 2/3 (copy2.exr): given twice (also p2.exr)"},
        {"p1.exr seed2.exr p3.exr", "share 2/3 (seed2.exr): another seed: seed '8' (the other shares: '7')"},
        {"p1.exr pinhole2.exr p3.exr", "share 2/3 (pinhole2.exr): another setting: pinhole '0.12mm' (the other shares: '0.1mm')"},
        {"p1.exr input2.exr p3.exr", "share 2/3 (input2.exr): made from another input (" + f.path("other.exr")},
        {"p1.exr split2.exr p3.exr", "share 2/4 (split2.exr): from a split into 4 shares; the other shares are of 3"},
        {"p1.exr cut2.exr p3.exr", "cut2.exr: cannot be read as an image ("},
        {"p1.exr edited2.exr p3.exr", "edited2.exr: corrupt: its pixels do not match the checksum in its header"},
        {"p1.exr text.exr p3.exr", "text.exr: cannot be read as an image ("},
        {"p1.exr decided2.exr p3.exr",
         "share 2/3 (decided2.exr): decided otherwise: 550nm direct/direct on gpu (the other shares: "},
        {"p1.exr " + f.input + " p3.exr", f.input + ": not a wavecam share file"},
        {"'none*.exr'", "none*.exr: no share files match this pattern"},
    };
    for (const auto& c : cases) {
        auto r = f.merge(c.shares, "out.exr");
        EXPECT_NE(r.status, 0) << c.shares;
        EXPECT_NE(r.output.find("refused, nothing written"), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(c.expected), std::string::npos) << c.shares << "\n" << r.output;
        EXPECT_FALSE(fs::exists(f.path("out.exr"))) << c.shares;
    }
    // the input changed after the shares were computed
    write_render(f.input, 24, 16, 2.5f, 30.0f);
    auto r = f.merge("p1.exr p2.exr p3.exr", "out.exr");
    EXPECT_NE(r.output.find("changed since the shares were computed"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(f.path("out.exr")));
}

TEST(Shares, ShareFlagErrorsAndACompleteShareIsKept) {
    Fixture f("shares_flags");
    auto bad = f.share(5, 4, "x.exr");
    EXPECT_EQ(WEXITSTATUS(bad.status), 2) << bad.output;
    EXPECT_NE(bad.output.find("--share: expected K/N with 1 <= K <= N"), std::string::npos) << bad.output;
    auto many = f.share(1, 24 * 16 * 6 + 1, "x.exr");
    EXPECT_NE(many.output.find("more than the job's 6 units x 16 film rows"), std::string::npos) << many.output;
    auto fast = run_command(kWavecam + " apply " + f.input + " -o " + f.path("x.exr") + " --share 1/2 --fov 30deg");
    EXPECT_NE(fast.output.find("expected method random-phase or incoherent (--method)"), std::string::npos) << fast.output;
    EXPECT_FALSE(fs::exists(f.path("x.exr")));
    // the share's own terms are bounded, and the message describes the job
    auto big = f.share(1, 2, "x.exr", " --max-terms 1e6");
    EXPECT_NE(big.output.find("share 1/2 of 24x16 pixels x 3 wavelengths x 2 runs"), std::string::npos) << big.output;
    EXPECT_NE(big.output.find("beyond the max-terms limit of 1e+06"), std::string::npos) << big.output;
    EXPECT_NE(big.output.find("raise --max-terms"), std::string::npos) << big.output;
    // a re-run task keeps a complete share file of the same job (a killed task is simply re-run)
    ASSERT_EQ(f.share(1, 2, "p1.exr").status, 0);
    const auto written = fs::last_write_time(f.path("p1.exr"));
    auto again = f.share(1, 2, "p1.exr");
    EXPECT_NE(again.output.find("already complete; kept"), std::string::npos) << again.output;
    EXPECT_EQ(fs::last_write_time(f.path("p1.exr")), written);
    // ...but not one of another seed
    auto other = f.share(1, 2, "p1.exr", " --seed 9");
    EXPECT_EQ(other.output.find("already complete"), std::string::npos) << other.output;
}

// `--part K/N` is --share's other spelling: the same share file, with one note on standard error
// (`--help` lists --share alone, and the two given with different shares are refused). A share
// file whose header spells its records wavecam.part.* is read as one spelt wavecam.share.*: kept
// by a re-run task, merged to the same image, with one note.
TEST(Shares, ThePartSpellingOfTheShareFlagAndRecordsIsReadWithANote) {
    Fixture f("shares_spelling");
    auto count = [](const std::string& text, const std::string& line) {
        size_t n = 0;
        for (size_t at = text.find(line); at != std::string::npos; at = text.find(line, at + 1)) ++n;
        return n;
    };
    const std::string flag_note = "wavecam: --part is now spelt --share (same meaning)";
    const std::string record_note = std::string("wavecam: ") + wavecam::kOldShareRecordNote;
    auto s1 = f.share(1, 2, "s1.exr"), s2 = f.share(2, 2, "s2.exr");
    ASSERT_EQ(s1.status, 0) << s1.output;
    ASSERT_EQ(s2.status, 0) << s2.output;
    EXPECT_EQ(s2.output.find("--part"), std::string::npos) << s2.output;
    auto p2 = f.share(2, 2, "p2.exr", "", "--part");
    ASSERT_EQ(p2.status, 0) << p2.output;
    EXPECT_EQ(count(p2.output, flag_note), 1u) << p2.output;
    EXPECT_NE(p2.output.find("share 2/2 ("), std::string::npos) << p2.output;
    const OIIO::ImageBuf by_share = read_float(f.path("s2.exr")), by_part = read_float(f.path("p2.exr"));
    EXPECT_EQ(by_part.spec().get_string_attribute("wavecam.share"), "2/2");
    EXPECT_EQ(by_part.spec().get_string_attribute("wavecam.share.job"),
              by_share.spec().get_string_attribute("wavecam.share.job"));
    EXPECT_EQ(max_difference(f.path("s2.exr"), f.path("p2.exr")), 0.0f);
    auto merged = f.merge("s1.exr p2.exr", "merged.exr");
    ASSERT_EQ(merged.status, 0) << merged.output;

    auto both = run_command(kWavecam + " apply " + f.input + " -o " + f.path("x.exr") + job() +
                            " --share 1/2 --part 2/2");
    EXPECT_EQ(WEXITSTATUS(both.status), 2) << both.output;
    EXPECT_NE(both.output.find("--share 1/2 and --part 2/2: one flag given twice"), std::string::npos) << both.output;
    EXPECT_FALSE(fs::exists(f.path("x.exr")));
    auto help = run_command(kWavecam + " apply --help");
    EXPECT_NE(help.output.find("--share"), std::string::npos) << help.output;
    EXPECT_EQ(help.output.find("--part"), std::string::npos) << help.output;

    {  // share 2/2 with its records spelt wavecam.part.share and wavecam.part.NAME
        OIIO::ImageBuf old = read_float(f.path("s2.exr"));
        OIIO::ImageSpec& spec = old.specmod();
        OIIO::ParamValueList respelt;
        for (const OIIO::ParamValue& a : spec.extra_attribs) {
            const std::string name = a.name().string();
            if (name == "wavecam.share")
                respelt.push_back(OIIO::ParamValue("wavecam.part.share", a.type(), 1, a.data()));
            else if (name.rfind("wavecam.share.", 0) == 0)
                respelt.push_back(OIIO::ParamValue("wavecam.part." + name.substr(14), a.type(), 1, a.data()));
            else
                respelt.push_back(a);
        }
        spec.extra_attribs = respelt;
        ASSERT_TRUE(old.write(f.path("old2.exr"))) << old.geterror();
    }
    const OIIO::ImageBuf old = read_float(f.path("old2.exr"));
    EXPECT_EQ(old.spec().get_string_attribute("wavecam.share"), "");
    EXPECT_EQ(old.spec().get_string_attribute("wavecam.part.share"), "2/2");
    auto kept = f.share(2, 2, "old2.exr");
    EXPECT_NE(kept.output.find("already complete; kept"), std::string::npos) << kept.output;
    EXPECT_EQ(count(kept.output, record_note), 1u) << kept.output;
    auto merged_old = f.merge("s1.exr old2.exr", "merged_old.exr");
    ASSERT_EQ(merged_old.status, 0) << merged_old.output;
    EXPECT_EQ(count(merged_old.output, record_note), 1u) << merged_old.output;
    EXPECT_EQ(count(merged.output, record_note), 0u) << merged.output;
    EXPECT_EQ(max_difference(f.path("merged.exr"), f.path("merged_old.exr")), 0.0f);
}

// Monochrome light diffracts each channel on its own (three propagations per wavelength): its
// shares carry all three and merge into the single run's image bit for bit, grey staying grey.
TEST(Shares, MonochromeSharesMergeEqualToTheSingleRun) {
    Fixture f("shares_mono");
    const std::string mono = " --wavelengths 550nm";
    auto single = run_command(kWavecam + " apply " + f.input + " -o " + f.path("single.exr") + job_with(mono));
    ASSERT_EQ(single.status, 0) << single.output;
    for (int n : {2, 5}) {
        for (int k = 1; k <= n; ++k) {
            auto r = f.share(k, n, "n" + std::to_string(n) + "_share" + std::to_string(k) + ".exr", mono);
            ASSERT_EQ(r.status, 0) << r.output;
        }
        OIIO::ImageBuf last(f.path("n" + std::to_string(n) + "_share" + std::to_string(n) + ".exr"));
        ASSERT_TRUE(last.read());
        // the last share holds run 2 of the one wavelength: every channel's propagation
        for (const char* c : {"w000.r001.pos", "w001.r001.pos", "w002.r001.pos"})
            EXPECT_GE(last.spec().channelindex(c), 0) << c << " in share " << n << "/" << n;
        const std::string out = "merged" + std::to_string(n) + ".exr";
        auto m = f.merge("'n" + std::to_string(n) + "_share*.exr'", out);
        ASSERT_EQ(m.status, 0) << m.output;
        EXPECT_EQ(max_difference(f.path("single.exr"), f.path(out)), 0.0f) << n << " shares";
    }
    OIIO::ImageBuf img(f.path("single.exr"));
    ASSERT_TRUE(img.read(0, 0, true, OIIO::TypeDesc::FLOAT));
    EXPECT_NE(img.spec().get_string_attribute("wavecam.light").find("monochrome"), std::string::npos);
    EXPECT_GT(max_difference(f.path("single.exr"), f.input), 1e-3f);
}

// The scene-sum methods' cost: one propagation per wavelength for colour, three for monochrome
// light whether asked for (--monochrome) or found (549, 550, 551 nm cannot carry colour); against
// the per-wavelength terms summed here.
TEST(Shares, EstimateCountsMonochromeLightThreeTimes) {
    wavecam::PinholeCamera camera;
    camera.width = 24;
    camera.height = 16;
    camera.fov_h = 30 * M_PI / 180;
    camera.film_distance = 20e-3;
    const std::vector<float> depth(24 * 16, 2.0f);
    wavecam::DiffractOptions opt;
    opt.method = wavecam::DiffractMethod::RandomPhase;
    opt.colorconfig = std::string(WAVECAM_SOURCE_DIR) + "/ocio_configs/wavecam.ocio";
    opt.film_distance = 20e-3;
    opt.pinhole = 0.1e-3;
    opt.scene_sum.runs = 2;  // kJob's
    opt.scene_sum.summation = test_summation();
    opt.device = test_device().setting();
    opt.scene_sum.film_subsamples = 1;
    auto per_wavelength = [&](const std::vector<double>& wavelengths) {
        wavecam::SceneSumSettings s = opt.scene_sum;
        s.aperture = wavecam::resolved_aperture(opt);
        s.nearest_depth = wavecam::nearest_depth(camera, depth.data(), opt.depth_meaning);
        // `auto` decided as a job decides it: once, at the middle of its wavelengths
        const wavecam::ComputeDevice cpu;  // (the job's estimate, as on the CPU)
        s.summation = wavecam::chosen_summation(s, cpu, camera, wavelengths[wavelengths.size() / 2]);
        double sum = 0;
        for (double l : wavelengths) sum += wavecam::scene_terms(s, cpu, camera, l);
        return sum;
    };
    const std::vector<double> colour = {450e-9, 550e-9, 650e-9}, close = {549e-9, 550e-9, 551e-9};
    opt.wavelengths = colour;
    const double terms_colour = estimate_terms(opt, camera, depth);
    EXPECT_NEAR(terms_colour / per_wavelength(colour), 1.0, 1e-12);
    opt.monochrome = true;  // asked for
    EXPECT_NEAR(estimate_terms(opt, camera, depth) / per_wavelength(colour), 3.0, 1e-12);
    opt.monochrome = false;
    opt.wavelengths = close;  // found
    EXPECT_NEAR(estimate_terms(opt, camera, depth) / per_wavelength(close), 3.0, 1e-12);
    opt.wavelengths = {550e-9};  // one wavelength
    EXPECT_NEAR(estimate_terms(opt, camera, depth) / per_wavelength({550e-9}), 3.0, 1e-12);
    // and the command refuses the job with those terms (kJob's render: 24 x 16, 30deg, depth 2 m)
    Fixture f("shares_estimate");
    auto r = run_command(kWavecam + " apply " + f.input + " -o " + f.path("x.exr") +
                         job_with(" --wavelengths 549nm,550nm,551nm --max-terms 1"));
    // "... 2 runs, direct summation[ on DEVICE] = 5.5e+08 terms"
    const size_t at = r.output.find(" = ", r.output.find(" summation"));
    ASSERT_NE(at, std::string::npos) << r.output;
    EXPECT_NEAR(std::stod(r.output.substr(at + 3)) / per_wavelength(close), 3.0, 1e-4) << r.output;
}

// Every split of every small job shape: 1-3 wavelengths (1 and 2 are monochrome light, three
// propagations per wavelength; 3 is colour) x 1-3 runs, into 1-4 shares (fewer shares than
// units, as many, and more: bands of rows). Each split, written as share files, read back, checked
// as a set and merged, equals the single run bit for bit. In-process, on a 4 x 4 frame, so that
// the 36 splits take a few seconds.
TEST(Shares, EverySplitOfEveryJobShapeMergesToTheSingleRun) {
    const fs::path dir = scratch("shares_every_split");
    const std::string input = (dir / "in.exr").string();
    {
        OIIO::ImageSpec spec(4, 4, 4, OIIO::TypeDesc::FLOAT);
        spec.channelnames = {"R", "G", "B", "Z"};
        spec.attribute("wavecam.fov", 30.0f);
        OIIO::ImageBuf in(spec);
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) {
                // saturated primaries among greys: negative spectral power at some wavelengths
                const float px[4][4] = {{1, 0, 0, 2}, {0.4f, 0.4f, 0.4f, 2}, {0, 0, 1, 2}, {0.1f, 0.6f, 0.2f, 2}};
                in.setpixel(i, j, px[(i + j) % 4]);
            }
        ASSERT_TRUE(in.write(input));
    }
    OIIO::ImageBuf src(input);
    ASSERT_TRUE(src.read(0, 0, true, OIIO::TypeDesc::FLOAT));
    int negative_channels = 0;
    for (int waves = 1; waves <= 3; ++waves)
        for (int runs = 1; runs <= 3; ++runs) {
            wavecam::DiffractOptions opt;
            opt.method = wavecam::DiffractMethod::RandomPhase;
            opt.colorconfig = std::string(WAVECAM_SOURCE_DIR) + "/ocio_configs/wavecam.ocio";
            opt.film_distance = 20e-3;
            opt.pinhole = 0.04e-3;
            opt.wavelength_count = waves;
            opt.scene_sum.runs = runs;
            opt.scene_sum.film_subsamples = 1;
            opt.scene_sum.seed = 7;
            const std::string shape = std::to_string(waves) + " wavelengths x " + std::to_string(runs) + " runs";
            OIIO::ImageBuf single;
            auto s = wavecam::DiffractPlan(opt).diffract(single, src, input, 1);
            ASSERT_TRUE(s.ok()) << shape << ": " << s.error;
            const wavecam::SettingsText settings = {{"wavelengths", std::to_string(waves)},
                                                    {"runs", std::to_string(runs)}};
            for (int n = 1; n <= 4; ++n) {
                std::vector<wavecam::ShareFile> shares;
                for (int k = 1; k <= n; ++k) {
                    OIIO::ImageBuf share;
                    auto r = wavecam::diffract_share(share, src, opt, {input, settings}, {k, n}, 1);
                    ASSERT_TRUE(r.ok()) << shape << ", share " << k << "/" << n << ": " << r.error;
                    // a name of its own per split (OIIO's image cache knows a name read before)
                    const std::string path = (dir / ("w" + std::to_string(waves) + "r" + std::to_string(runs) + "_" +
                                                     std::to_string(k) + "of" + std::to_string(n) + ".exr"))
                                                 .string();
                    auto w = wavecam::write_image_atomically(share, path, OIIO::TypeDesc::FLOAT);
                    ASSERT_TRUE(w.ok()) << w.error;
                    auto p = wavecam::read_share(path);
                    ASSERT_TRUE(p.ok()) << shape << ", share " << k << "/" << n << ": " << p.error;
                    for (const auto& name : p.value.image.spec().channelnames)
                        negative_channels += name.find(".neg") != std::string::npos;
                    shares.push_back(std::move(p.value));
                }
                auto set = wavecam::check_share_set(shares);
                ASSERT_TRUE(set.ok()) << shape << ", " << n << " shares: " << set.error;
                wavecam::DiffractOptions merge = opt;
                merge.max_terms = INFINITY;
                merge.scene_sum_propagator = wavecam::stored_units(shares);
                OIIO::ImageBuf merged;
                auto m = wavecam::DiffractPlan(merge).diffract(merged, src, input, 1);
                ASSERT_TRUE(m.ok()) << shape << ", " << n << " shares: " << m.error;
                ASSERT_EQ(merged.spec().image_pixels(), single.spec().image_pixels());
                ASSERT_EQ(merged.nchannels(), single.nchannels());
                std::vector<float> a(single.spec().image_pixels() * single.nchannels()), b(a.size());
                single.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, a.data());
                merged.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, b.data());
                EXPECT_EQ(a, b) << shape << ", " << n << " shares";
                EXPECT_GT(*std::max_element(a.begin(), a.end()), 0.0f) << shape;
            }
        }
    EXPECT_GT(negative_channels, 0) << "the test should cover negative spectral power";
    fs::remove_all(dir);
}
