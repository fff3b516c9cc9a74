// `wavecam estimate`: what `wavecam apply` would cost, before the render exists or without the
// work: the same job line, terms, time at the rate measured here and peak memory, and the refusal
// the job would meet. A frame is a render (the EXR apply would read) or a description of one:
// its size, field of view and nearest depth (every pixel lit at that depth, as the chooser
// counts a frame), which is all the estimate reads of a render.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <unistd.h>

#include <cstdio>
#include <memory>

#include "commands.h"
#include "terminal_progress.h"
#include "wavecam/diffract_image.h"
#include "wavecam/threads.h"
#include "wavecam/units.h"
#include "../front/settings.h"

namespace wavecam::cli {
namespace {

struct EstimateFlags {
    std::string input, size, nearest;
    front::Settings given;
    int threads = 0;
};

int fail(const std::string& message, int status) {
    std::fprintf(stderr, "wavecam estimate: %s\n", message.c_str());
    return status;
}

// "1920x1080": a frame's width and height in pixels, each 1 to 16384.
Result<std::pair<int, int>> parse_size(const std::string& text) {
    using R = Result<std::pair<int, int>>;
    const size_t x = text.find('x');
    const auto bad = R::failure("--size: expected WIDTHxHEIGHT in pixels, each 1 to 16384 (e.g. 1920x1080), got '" +
                                text + "'");
    if (x == std::string::npos) return bad;
    auto w = parse_whole_number(text.substr(0, x), "--size", 1, 16384);
    auto h = parse_whole_number(text.substr(x + 1), "--size", 1, 16384);
    if (!w.ok() || !h.ok()) return bad;
    return R::success({int(w.value), int(h.value)});
}

// The frame a description stands for: RGB 1 and depth `nearest` metres (in the depth channel's
// units, `depth_scale` metres each) at every pixel; its fov comes from the settings.
OIIO::ImageBuf described_frame(int width, int height, double nearest, double depth_scale) {
    OIIO::ImageSpec spec(width, height, 4, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "Z"};
    OIIO::ImageBuf frame(spec);
    const float values[4] = {1.0f, 1.0f, 1.0f, float(nearest / depth_scale)};
    OIIO::ImageBufAlgo::fill(frame, values);
    return frame;
}

// The bytes this process holds now (its libraries, mapped and touched: about 130 MiB), which a
// job's peak holds too.
double resident_bytes() {
    long pages = 0, resident = 0;
    if (std::FILE* f = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
        std::fclose(f);
    }
    return double(resident) * double(::sysconf(_SC_PAGESIZE));
}

int run(const EstimateFlags& flags) {
    const double process = resident_bytes();  // (before the frame is read)
    if (auto t = parse_threads(flags.threads); !t.ok()) return fail("--" + t.error, 2);
    const bool described = !flags.size.empty() || !flags.nearest.empty();
    if (described == !flags.input.empty())
        return fail("expected a render (the EXR `wavecam apply` would read) or a description of one (--size, "
                    "--nearest and --fov), not both",
                    2);
    ResolvedInput in;
    std::string name = flags.input;
    if (!described) {
        auto read = read_and_resolve(flags.input, flags.given);
        if (!read.ok()) return fail(read.error, 2);
        in = std::move(read.value);
    } else {
        if (flags.size.empty() || flags.nearest.empty() || !flags.given.count("fov"))
            return fail("a described frame needs --size (e.g. 1920x1080), --nearest (the nearest visible depth, "
                        "e.g. 2.5m, or inf for sky alone) and --fov (e.g. 50deg)",
                        2);
        auto size = parse_size(flags.size);
        if (!size.ok()) return fail(size.error, 2);
        auto nearest = parse_length_or_inf(flags.nearest, "--nearest");
        if (!nearest.ok()) return fail(nearest.error, 2);
        name = flags.size + " frame";
        front::SettingSources sources;
        sources.given = flags.given;
        sources.given_name = [](const std::string& key) { return "--" + key; };
        auto settings = front::resolve_settings(OIIO::ImageSpec(size.value.first, size.value.second, 4), sources);
        if (!settings.ok()) return fail(settings.error, 2);
        front::show_notes(settings.value.notes);
        in.settings = std::move(settings.value);
        in.image = described_frame(size.value.first, size.value.second, nearest.value,
                                   in.settings.options.read.depth_scale);
    }
    DiffractPlan plan(in.settings.options);
    auto e = plan.estimate(in.image, name, flags.threads);
    if (!e.ok()) return fail(front::word_failure(Result<bool>::failure(e), front::Front::Command), 2);
    const JobEstimate& j = e.value;
    if (j.rate > 0) print_estimate("estimate", j);
    else std::fprintf(stderr, "estimate: %s: no scene sums (a PSF grid and FFTs); not timed\n", j.job.c_str());
    std::fprintf(stderr, "estimate: about %.0f MiB at the peak\n", (j.bytes + process) / (1 << 20));
    std::fprintf(stderr, "estimate: threads: %d, each asleep after a short spin when it waits\n",
                 flags.threads > 0 ? flags.threads : default_threads());
    if (!j.refusal.empty()) return fail(j.refusal, 1);
    return 0;
}

}  // namespace

void add_estimate_command(CLI::App& app, int& status) {
    auto f = std::make_shared<EstimateFlags>();
    CLI::App* cmd = app.add_subcommand(
        "estimate", "Say what `wavecam apply` would cost (time, terms, memory, refusals), without the work");
    cmd->add_option("input", f->input, "The render `wavecam apply` would read (or describe one: --size, --nearest)");
    cmd->add_option("--size", f->size, "A described frame's size in pixels, e.g. 1920x1080");
    cmd->add_option("--nearest", f->nearest, "A described frame's nearest visible depth, e.g. 2.5m (inf: sky alone)");
    add_setting_options(cmd, f->given);
    cmd->add_option("--threads", f->threads, "Threads the job would run on (0 = every core)")->capture_default_str();
    cmd->callback([f, &status] { status = run(*f); });
}

}  // namespace wavecam::cli
