// `wavecam apply`: a render (RGB + depth EXR) in, the real pinhole camera's image out.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>

#include <cstdio>
#include <filesystem>
#include <memory>

#include "commands.h"
#include "compare_sheet.h"
#include "terminal_progress.h"
#include "wavecam/atomic_write.h"
#include "wavecam/diffract_image.h"
#include "wavecam/share_files.h"
#include "wavecam/units.h"
#include "../front/settings.h"

namespace wavecam::cli {

front::Settings recorded_settings(const front::Settings& given) {
    front::Settings settings = given;
    settings.erase("max-terms");
    settings.erase("max-memory");
    return settings;
}

void add_setting_options(CLI::App* cmd, front::Settings& given) {
    for (const front::SettingKey& k : front::setting_keys()) {
        const std::string& key = k.key;
        if (key == "jitter" || key == "vignetting") continue;  // flags below
        if (key == "monochrome") {
            cmd->add_flag_callback("--monochrome", [&given] { given["monochrome"] = "true"; }, k.help);
            continue;
        }
        cmd->add_option_function<std::string>("--" + key, [&given, key](const std::string& v) { given[key] = v; },
                                              k.help)
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    }
    cmd->add_flag_callback("--no-jitter", [&given] { given["jitter"] = "false"; },
                           "Keep each source at its pixel centre");
    cmd->add_flag_callback("--no-vignetting", [&given] { given["vignetting"] = "false"; },
                           "Divide out the natural cos^4 fall-off");
}

Result<ResolvedInput> read_and_resolve(const std::string& input, const front::Settings& given) {
    double max_bytes = DiffractOptions{}.max_memory;  // the limit given, before the render is read
    if (auto limit = given.find("max-memory"); limit != given.end())
        if (auto b = parse_bytes(limit->second, "--max-memory"); b.ok()) max_bytes = b.value;
    auto image = read_image(input, max_bytes);
    if (!image.ok()) return Result<ResolvedInput>::failure(image);
    ResolvedInput r{std::move(image.value), {}};
    front::SettingSources sources;
    sources.given = given;
    sources.given_name = [](const std::string& key) { return "--" + key; };
    auto settings = front::resolve_settings(r.image.spec(), sources);
    if (!settings.ok()) return Result<ResolvedInput>::failure(input + ": " + settings.error);
    r.settings = std::move(settings.value);
    return Result<ResolvedInput>::success(std::move(r));
}

Result<std::vector<std::string>> frame_files(const std::string& pattern, const std::vector<int>& frames) {
    std::string normalized, ignored;
    std::vector<std::string> files;
    if (!OIIO::Filesystem::parse_pattern(pattern.c_str(), 0, normalized, ignored) ||
        !OIIO::Filesystem::enumerate_file_sequence(normalized, frames, files) ||
        (frames.size() > 1 && files.front() == files.back()))
        return Result<std::vector<std::string>>::failure(
            "--frames: '" + pattern + "' has no frame number pattern; expected #, @ or %04d in the name");
    return Result<std::vector<std::string>>::success(files);
}

namespace {

struct ApplyFlags {
    std::string input, output, compare, png, frames, part;
    front::Settings given;  // the settings flags that were given, by key (--no-jitter as jitter=false)
    int threads = 0;
};

int fail(const std::string& message, int status = 1) {
    finish_progress();
    if (status == 1 && interrupted()) status = interrupted_status();  // (a write refused at a signal)
    std::fprintf(stderr, "wavecam apply: %s\n", message.c_str());
    return status;
}

bool is_exr(const std::string& path) { return OIIO::Strutil::iequals(OIIO::Filesystem::extension(path), ".exr"); }

// Output names are checked before any work: OpenEXR, or a display-referred PNG, JPEG or TIFF.
std::string unsupported_output(const ApplyFlags& flags) {
    if (!is_exr(flags.output) && display_format(flags.output) == OIIO::TypeDesc::UNKNOWN)
        return flags.output + ": unsupported output format; expected .exr (scene-linear float, alpha and depth "
                              "kept) or a display-referred .png, .jpg (8-bit) or .tif (16-bit), RGB only";
    if (!flags.png.empty() && display_format(flags.png) == OIIO::TypeDesc::UNKNOWN)
        return "--png " + flags.png + ": expected a .png, .jpg or .tif name";
    return {};
}

// A resolved input's options, with this run's progress and its estimates printed before work.
DiffractOptions run_options(const ResolvedInput& in, const ProgressFn& progress, int threads) {
    DiffractOptions o = in.settings.options;
    o.progress = progress;
    o.on_estimate = [threads](const std::string& job, double terms) { print_estimate("apply", job, terms, threads); };
    return o;
}

int fail_with(const Result<bool>& r) {
    return fail(front::word_failure(r, front::Front::Command), r.kind == ErrorKind::Cancelled || interrupted() ? interrupted_status() : 1);
}

// One share of an exact job (--part K/N): a part file for `wavecam merge`. A part already there
// for the same job and share is kept, so a re-run array task finishes at once.
int run_share(const ApplyFlags& flags, const std::string& input, const std::string& output) {
    auto k = parse_share(flags.part);
    if (!k.ok()) return fail(k.error, 2);
    std::error_code ec;
    const std::string input_path = std::filesystem::absolute(input, ec).lexically_normal().string();
    const front::Settings settings = recorded_settings(flags.given);
    if (std::filesystem::exists(output, ec)) {
        auto have = read_part(output);
        auto fingerprint = file_fingerprint(input_path);
        if (have.ok() && fingerprint.ok() && have.value.job == job_fingerprint(fingerprint.value, settings) &&
            have.value.share.index == k.value.index && have.value.share.count == k.value.count) {
            std::printf("%s: share %s already complete; kept\n", output.c_str(), flags.part.c_str());
            return 0;
        }
    }
    auto in = read_and_resolve(input, flags.given);
    if (!in.ok()) return fail(in.error, 2);
    const DiffractOptions o = run_options(in.value, terminal_progress("apply share " + flags.part), flags.threads);
    OIIO::ImageBuf part;
    if (auto r = diffract_share(part, in.value.image, input_path, o, settings, k.value.index, k.value.count,
                                flags.threads);
        !r.ok())
        return fail_with(r);
    finish_progress();
    if (interrupted()) return fail(input + ": interrupted", interrupted_status());
    if (auto w = write_image_atomically(part, output, OIIO::TypeDesc::FLOAT); !w.ok()) return fail(w.error);
    std::printf("share %s (%s)\nwrote %s\n", flags.part.c_str(),
                part.spec().get_string_attribute("wavecam.part.summed").c_str(), output.c_str());
    return 0;
}

// One frame: read, resolve its settings, diffract, write (and the pictures for people). `plan`
// is kept for the next frame while the settings stay the same (a sequence pays for one PSF table).
int run_frame(const ApplyFlags& flags, std::unique_ptr<DiffractPlan>& plan, front::Settings& plan_settings,
              const ProgressFn& progress, const std::string& input, const std::string& output,
              const std::string& compare, const std::string& png) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(output, ec) && fs::equivalent(input, output, ec))
        return fail(output + ": the output would overwrite the input; choose another -o", 2);
    set_interrupt_message("wavecam apply: " + input + ": interrupted");
    if (!flags.part.empty()) return run_share(flags, input, output);
    auto in = read_and_resolve(input, flags.given);
    if (!in.ok()) return fail(in.error, 2);
    const OIIO::ImageBuf& src = in.value.image;
    if (!plan || plan_settings != in.value.settings.text) {
        plan = std::make_unique<DiffractPlan>(run_options(in.value, progress, flags.threads));
        plan_settings = in.value.settings.text;
    }
    OIIO::ImageBuf dst;
    if (auto r = plan->diffract(dst, src, input, flags.threads); !r.ok()) return fail_with(r);
    if (interrupted()) return fail(input + ": interrupted", interrupted_status());  // nothing written
    const DiffractOptions& opt = plan->options();
    finish_progress();
    // the job this image is (input bytes and settings): `wavecam farm` skips frames already made
    if (auto fingerprint = file_fingerprint(input); fingerprint.ok())
        dst.specmod().attribute("wavecam.job",
                                job_fingerprint(fingerprint.value, recorded_settings(flags.given)));
    // OpenEXR: scene-linear float, every channel; .png/.jpg/.tif: RGB through the display view
    auto written = is_exr(output) ? write_image_atomically(dst, output, OIIO::TypeDesc::FLOAT)
                                  : write_display_image(dst, opt, output);
    if (!written.ok()) return fail(written.error);
    if (!compare.empty())
        if (auto w = write_compare_sheet(src, dst, opt, compare); !w.ok()) return fail(w.error);
    if (!png.empty())
        if (auto w = write_display_image(dst, opt, png); !w.ok()) return fail(w.error);
    std::printf("pinhole %s, %s\n", dst.spec().get_string_attribute("wavecam.pinhole").c_str(),
                dst.spec().get_string_attribute("wavecam.summary").c_str());
    std::printf("wrote %s\n", output.c_str());
    return 0;
}

int run(const ApplyFlags& flags) {
    if (const std::string bad = unsupported_output(flags); !bad.empty()) return fail(bad, 2);
    for (const std::string* name : {&flags.output, &flags.compare, &flags.png})  // before any work
        if (!name->empty())
            if (const std::string bad = output_name_problem(*name); !bad.empty()) return fail(bad, 2);
    if (!flags.part.empty() && (!flags.compare.empty() || !flags.png.empty()))
        return fail("--part writes a part file for `wavecam merge`; give --compare and --png to the merge instead", 2);
    std::unique_ptr<DiffractPlan> plan;
    front::Settings plan_settings;
    if (flags.frames.empty())
        return run_frame(flags, plan, plan_settings, terminal_progress("apply"), flags.input, flags.output,
                         flags.compare, flags.png);

    std::vector<int> frames;
    if (!OIIO::Filesystem::enumerate_sequence(flags.frames, frames) || frames.empty())
        return fail("--frames: expected a frame range such as 1-100, 1-100x2 or 3,7,10-20, got '" + flags.frames +
                    "'", 2);
    std::vector<std::string> lists[4];
    const std::string* patterns[4] = {&flags.input, &flags.output, &flags.compare, &flags.png};
    for (int k = 0; k < 4; ++k) {
        lists[k].assign(frames.size(), "");
        if (patterns[k]->empty()) continue;
        auto files = frame_files(*patterns[k], frames);
        if (!files.ok()) return fail(files.error, 2);
        lists[k] = files.value;
    }
    // one plan while the frames' settings agree: the PSF table is built once and reused
    auto bar = std::make_shared<ProgressFn>();
    const ProgressFn progress = [bar](double f) { return (*bar)(f); };
    for (size_t f = 0; f < frames.size(); ++f) {
        *bar = terminal_progress("apply frame " + std::to_string(frames[f]));
        if (const int status = run_frame(flags, plan, plan_settings, progress, lists[0][f], lists[1][f], lists[2][f],
                                         lists[3][f]);
            status != 0)
            return status;
    }
    return 0;
}

}  // namespace

void add_apply_command(CLI::App& app, int& status) {
    auto f = std::make_shared<ApplyFlags>();
    CLI::App* cmd = app.add_subcommand("apply", "Diffract a render (RGB radiance + depth) through a real pinhole");
    cmd->add_option("input", f->input, "Input EXR: linear RGB radiance and depth")->required();
    cmd->add_option("-o,--output", f->output,
                    "Output: .exr (float RGB, the input's alpha and depth, its channel names) or a display-referred "
                    ".png/.jpg (8-bit) or .tif (16-bit), RGB through the sRGB display's Standard view")->required();
    add_setting_options(cmd, f->given);
    cmd->add_option("--compare", f->compare, "Write input | output | difference as a PNG through the display view");
    cmd->add_option("--png", f->png, "Also write the output as a display-referred PNG");
    cmd->add_option("--frames", f->frames,
                    "Frame range, e.g. 1-100; input, -o, --compare and --png are then patterns (#, @ or %04d)");
    cmd->add_option("--threads", f->threads, "Threads (0 = every core)")->capture_default_str();
    cmd->add_option("--part", f->part,
                    "K/N: compute share K of N of an exact job and write it to -o as a part file for "
                    "`wavecam merge` (see `wavecam farm`)");
    cmd->callback([f, &status] { status = run(*f); });
}

}  // namespace wavecam::cli
