// `wavecam apply`: a render (RGB + depth EXR) in, the real pinhole camera's image out.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>

#include <cstdio>
#include <filesystem>
#include <memory>

#include "commands.h"
#include "compare_sheet.h"
#include "output_paths.h"
#include "terminal_progress.h"
#include "wavecam/atomic_write.h"
#include "wavecam/diffract_image.h"
#include "wavecam/output_layout.h"
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
        if (key == "monochrome" || key == "diffract-again") {  // flags: true when given
            cmd->add_flag_callback("--" + key, [&given, key] { given[key] = "true"; }, k.help);
            continue;
        }
        cmd->add_option_function<std::string>("--" + key, [&given, key](const std::string& v) { given[key] = v; },
                                              k.help);
    }
    cmd->add_flag_callback("--no-jitter", [&given] { given["jitter"] = "false"; },
                           "Keep each source at its pixel centre");
    cmd->add_flag_callback("--no-vignetting", [&given] { given["vignetting"] = "false"; },
                           "Divide out the natural cos^4 fall-off");
}

Result<int> parse_threads(int threads) {
    if (threads < 0 || threads > 1024)
        return Result<int>::failure("threads: expected 0 (every core) to 1024 threads, got '" +
                                    std::to_string(threads) + "'");
    return Result<int>::success(threads);
}

Result<ResolvedInput> read_and_resolve(const std::string& input, const front::Settings& given) {
    double max_bytes = DiffractOptions{}.max_memory;  // the limit given, before the render is read
    if (auto limit = given.find("max-memory"); limit != given.end())
        if (auto b = parse_bytes(limit->second, "--max-memory"); b.ok()) max_bytes = b.value;
    const auto part = given.find("subimage");
    auto image = read_render(input, part == given.end() ? "" : part->second, max_bytes);
    if (!image.ok())  // (a part to name: how to name it)
        return Result<ResolvedInput>::failure(image.field == "subimage" ? front::word_failure(Result<bool>::failure(image),
                                                                                              front::Front::Command)
                                                                        : image.error);
    ResolvedInput r{std::move(image.value), {}};
    front::SettingSources sources;
    sources.given = given;
    sources.given_name = [](const std::string& key) { return "--" + key; };
    auto settings = front::resolve_settings(r.image.spec(), sources);
    if (!settings.ok()) return Result<ResolvedInput>::failure(input + ": " + settings.error);
    front::show_notes(settings.value.notes);
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
    std::string input, output, compare, png, frames, share;
    std::string share_old_spelling;  // --part K/N: --share's other spelling, taken with a note
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
DiffractOptions run_options(const ResolvedInput& in, const ProgressFn& progress) {
    DiffractOptions o = in.settings.options;
    o.progress = progress;
    o.on_estimate = [](const JobEstimate& e) { print_estimate("apply", e); };
    return o;
}

// What the aperture multiplies the work by, printed before it, at the densest sampling (400nm,
// every angle); "" when a zone plate's or sieve's samples fit in --max-memory, else why not
// (they are held at once).
std::string print_aperture_work(const DiffractOptions& o) {
    const Aperture aperture = resolved_aperture(o);
    const double samples = estimate_sample_count(aperture, sample_pitch(400e-9, 1.0));
    std::fprintf(stderr, "apply: pinhole %.4gmm, %s\n", aperture.diameter * 1e3, aperture_work(aperture, samples).c_str());
    const double bytes = samples * 3 * sizeof(float);  // position and weight of each
    // (zones and holes multiply the samples; a plain shape's size is checked with the frame's geometry)
    const bool zones = aperture.shape == ApertureShape::ZonePlate || aperture.shape == ApertureShape::PhotonSieve;
    if (zones && !(bytes <= o.max_memory)) {
        char m[256];
        std::snprintf(m, sizeof m, "--aperture %s: about %.3g pinhole samples per PSF need %.3g GiB, beyond the "
                                   "max-memory limit of %.3g GiB; use fewer zones or holes, or a smaller --pinhole",
                      aperture.name().c_str(), samples, bytes / (1ull << 30), o.max_memory / (1ull << 30));
        return m;
    }
    return {};
}

int fail_with(const Result<bool>& r) {
    return fail(front::word_failure(r, front::Front::Command), r.kind == ErrorKind::Cancelled || interrupted() ? interrupted_status() : 1);
}

// One share of a scene-sum job (--share K/N): a share file for `wavecam merge`. A share file
// already there for the same job and share is kept, so a re-run array task finishes at once.
int run_share(const ApplyFlags& flags, const std::string& input, const std::string& output) {
    auto k = parse_share(flags.share);
    if (!k.ok()) return fail(k.error, 2);
    std::error_code ec;
    const std::string input_path = std::filesystem::absolute(input, ec).lexically_normal().string();
    const front::Settings settings = recorded_settings(flags.given);
    if (std::filesystem::exists(output, ec)) {
        auto have = read_share(output);
        auto fingerprint = file_fingerprint(input_path);
        if (have.ok() && fingerprint.ok() && have.value.job == job_fingerprint(fingerprint.value, settings) &&
            have.value.share.index == k.value.index && have.value.share.count == k.value.count) {
            if (have.value.old_spelling) front::show_notes({kOldShareRecordNote});
            std::printf("%s: share %s already complete; kept\n", output.c_str(), flags.share.c_str());
            return 0;
        }
    }
    auto in = read_and_resolve(input, flags.given);
    if (!in.ok()) return fail(in.error, 2);
    if (const std::string bad = print_aperture_work(in.value.settings.options); !bad.empty()) return fail(bad, 2);
    const DiffractOptions o = run_options(in.value, terminal_progress("apply share " + flags.share));
    OIIO::ImageBuf share;
    if (auto r = diffract_share(share, in.value.image, o, {input_path, settings}, k.value, flags.threads);
        !r.ok())
        return fail_with(r);
    finish_progress();
    if (interrupted()) return fail(input + ": interrupted", interrupted_status());
    if (auto w = write_image_atomically(share, output, OIIO::TypeDesc::FLOAT); !w.ok()) return fail(w.error);
    std::printf("share %s (%s)\nwrote %s\n", flags.share.c_str(), share_record(share.spec(), "summed").c_str(),
                output.c_str());
    return 0;
}

// One frame's files: the render it reads, the image it writes (-o) and the pictures for people
// (--compare, --png; "" for none).
struct FrameFiles {
    const std::string& input;
    const std::string& output;
    const std::string& compare;
    const std::string& png;
};

// One frame: read, resolve its settings, diffract, write (and the pictures for people). `plan`
// is kept for the next frame while the settings stay the same (a sequence pays for one kernel table).
int run_frame(const ApplyFlags& flags, std::unique_ptr<DiffractPlan>& plan, front::Settings& plan_settings,
              const ProgressFn& progress, const FrameFiles& files) {
    const std::string &input = files.input, &output = files.output, &compare = files.compare, &png = files.png;
    set_interrupt_message("wavecam apply: " + input + ": interrupted");
    if (!flags.share.empty()) return run_share(flags, input, output);
    auto in = read_and_resolve(input, flags.given);
    if (!in.ok()) return fail(in.error, 2);
    // a mask named by the render's own metadata (wavecam.aperture) is an input too
    if (auto a = in.value.settings.text.find("aperture"); a != in.value.settings.text.end())
        if (const std::string clash = path_conflict({{aperture_mask_file(a->second), input + "'s aperture mask"}},
                                                    {{output, "-o"}, {compare, "--compare"}, {png, "--png"}});
            !clash.empty())
            return fail(clash, 2);
    const OIIO::ImageBuf& src = in.value.image;
    if (!plan || plan_settings != in.value.settings.text) {
        if (const std::string bad = print_aperture_work(in.value.settings.options); !bad.empty()) return fail(bad, 2);
        plan = std::make_unique<DiffractPlan>(run_options(in.value, progress));
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
    if (is_exr(output)) {
        auto written = write_plate(dst, src, output, opt.pixel_type, opt.half_overflow, opt.max_memory);
        if (!written.ok()) return fail(written.error);
        if (!written.value.empty()) std::fprintf(stderr, "wavecam apply: %s: %s\n", output.c_str(), written.value.c_str());
    } else if (auto written = write_display_image(dst, opt, output); !written.ok()) {
        return fail(written.error);
    }
    if (!compare.empty())
        if (auto w = write_compare_sheet(src, dst, opt, compare); !w.ok()) return fail(w.error);
    if (!png.empty())
        if (auto w = write_display_image(dst, opt, png); !w.ok()) return fail(w.error);
    if (const std::string edge = dst.spec().get_string_attribute("wavecam.edge"); !edge.empty())
        std::fprintf(stderr, "wavecam apply: %s: %s\n", input.c_str(), edge.c_str());
    std::printf("pinhole %s, %s\n", dst.spec().get_string_attribute("wavecam.pinhole").c_str(),
                dst.spec().get_string_attribute("wavecam.summary").c_str());
    std::printf("wrote %s\n", output.c_str());
    return 0;
}

// Every path the run reads and writes, frame by frame: no output may be an input or another
// output, and every output's folder must be writable ("" when all is well).
std::string check_paths(const ApplyFlags& flags, const std::vector<int>& frames, const std::vector<std::string> (&lists)[4]) {
    static const char* const what[4] = {"the render", "-o", "--compare", "--png"};
    std::vector<PathUse> reads, writes;
    if (auto a = flags.given.find("aperture"); a != flags.given.end())
        reads.push_back({aperture_mask_file(a->second), "the --aperture mask"});
    for (size_t f = 0; f < lists[0].size(); ++f)
        for (int k = 0; k < 4; ++k) {
            const std::string name = flags.frames.empty() ? what[k] : std::string(what[k]) + " (frame " +
                                                                          std::to_string(frames[f]) + ")";
            (k == 0 ? reads : writes).push_back({lists[k][f], name});
        }
    return path_conflict(reads, writes);
}

int run(const ApplyFlags& flags) {
    if (auto t = parse_threads(flags.threads); !t.ok()) return fail("--" + t.error, 2);
    if (const std::string bad = unsupported_output(flags); !bad.empty()) return fail(bad, 2);
    for (const std::string* name : {&flags.output, &flags.compare, &flags.png})  // before any work
        if (!name->empty())
            if (const std::string bad = output_name_problem(*name); !bad.empty()) return fail(bad, 2);
    if (!flags.share.empty() && (!flags.compare.empty() || !flags.png.empty()))
        return fail("--share writes a share file for `wavecam merge`; give --compare and --png to the merge instead", 2);
    std::vector<int> frames{0};
    std::vector<std::string> lists[4] = {{flags.input}, {flags.output}, {flags.compare}, {flags.png}};
    if (!flags.frames.empty()) {
        auto numbers = frame_numbers(flags.frames);
        if (!numbers.ok()) return fail(numbers.error, 2);
        frames = numbers.value;
        const std::string* patterns[4] = {&flags.input, &flags.output, &flags.compare, &flags.png};
        for (int k = 0; k < 4; ++k) {
            lists[k].assign(frames.size(), "");
            if (patterns[k]->empty()) continue;
            auto files = frame_files(*patterns[k], frames);
            if (!files.ok()) return fail(files.error, 2);
            lists[k] = files.value;
        }
    }
    if (const std::string clash = check_paths(flags, frames, lists); !clash.empty()) return fail(clash, 2);
    std::unique_ptr<DiffractPlan> plan;
    front::Settings plan_settings;
    if (flags.frames.empty())
        return run_frame(flags, plan, plan_settings, terminal_progress("apply"),
                         {flags.input, flags.output, flags.compare, flags.png});
    // one plan while the frames' settings agree: the kernel table is built once and reused
    auto bar = std::make_shared<ProgressFn>();
    const ProgressFn progress = [bar](double f) { return (*bar)(f); };
    for (size_t f = 0; f < frames.size(); ++f) {
        *bar = terminal_progress("apply frame " + std::to_string(frames[f]));
        if (const int status = run_frame(flags, plan, plan_settings, progress,
                                         {lists[0][f], lists[1][f], lists[2][f], lists[3][f]});
            status != 0) {
            // the sequence stops at the first frame that fails: what was done, and what not
            std::fprintf(stderr, "wavecam apply: frames done: %s; failed: %d; not tried: %s\n",
                         frame_ranges({frames.begin(), frames.begin() + f}).c_str(), frames[f],
                         frame_ranges({frames.begin() + f + 1, frames.end()}).c_str());
            return status;
        }
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
    cmd->add_option("--share", f->share,
                    "K/N: compute share K of N of a scene-sum job and write it to -o as a share file for "
                    "`wavecam merge` (see `wavecam farm`)");
    cmd->add_option("--part", f->share_old_spelling, "--share's other spelling")->group("");  // (not in --help)
    cmd->callback([f, &status] {
        if (!f->share_old_spelling.empty()) {
            front::show_notes({"--part is now spelt --share (same meaning)"});
            if (!f->share.empty() && f->share != f->share_old_spelling) {
                status = fail("--share " + f->share + " and --part " + f->share_old_spelling +
                                  ": one flag given twice; give one --share K/N",
                              2);
                return;
            }
            f->share = f->share_old_spelling;
        }
        status = run(*f);
    });
}

}  // namespace wavecam::cli
