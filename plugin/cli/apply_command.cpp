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
#include "../front/settings.h"

namespace wavecam::cli {
namespace {

struct ApplyFlags {
    std::string input, output, compare, png, frames;
    front::Settings given;  // the settings flags that were given, by key
    bool no_vignetting = false, no_jitter = false;
    int threads = 0;
};

int fail(const std::string& message, int status = 1) {
    finish_progress();
    std::fprintf(stderr, "wavecam apply: %s\n", message.c_str());
    return status;
}

// One frame: read, diffract, write (and the pictures for people).
int run_frame(const ApplyFlags& flags, const DiffractOptions& opt, const std::string& input,
              const std::string& output, const std::string& compare, const std::string& png) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (fs::exists(output) && fs::equivalent(input, output, ec))
        return fail(output + ": the output would overwrite the input; choose another -o", 2);
    OIIO::ImageBuf src(input);
    if (!src.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
        std::string e = src.geterror();
        return fail(input + ": " + (e.empty() ? "cannot be read as an image" : e));
    }
    OIIO::ImageBuf dst;
    if (!diffract(dst, src, input, opt, flags.threads)) return fail(dst.geterror(), interrupted() ? 130 : 1);
    finish_progress();
    if (auto w = write_image_atomically(dst, output, OIIO::TypeDesc::FLOAT); !w.ok()) return fail(w.error);
    if (!compare.empty())
        if (auto w = write_compare_sheet(src, dst, opt, compare); !w.ok()) return fail(w.error);
    if (!png.empty())
        if (auto w = write_display_png(dst, opt, png); !w.ok()) return fail(w.error);
    std::printf("pinhole %s, %s\n", dst.spec().get_string_attribute("wavecam.pinhole").c_str(),
                dst.spec().get_string_attribute("wavecam.summary").c_str());
    std::printf("wrote %s\n", output.c_str());
    return 0;
}

// The files of a frame range: OIIO's own pattern rules ("shot.#.exr" = 4 digits, "@" = 1,
// "%04d" printf style) and sequence syntax ("1-100", "1-100x2", "3,7,10-20").
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

int run(const ApplyFlags& flags) {
    front::Settings settings = flags.given;
    if (flags.no_vignetting) settings["vignetting"] = "false";
    if (flags.no_jitter) settings["jitter"] = "false";
    auto options = front::options_from_settings(settings);
    if (!options.ok()) return fail("--" + options.error, 2);
    DiffractOptions opt = options.value;
    opt.progress = terminal_progress("apply");
    if (flags.frames.empty()) return run_frame(flags, opt, flags.input, flags.output, flags.compare, flags.png);

    std::vector<int> frames;
    if (!OIIO::Filesystem::enumerate_sequence(flags.frames, frames) || frames.empty())
        return fail("--frames: expected a frame range such as 1-100, 1-100x2 or 3,7,10-20, got '" + flags.frames +
                    "'", 2);
    std::vector<std::string> lists[4];
    const std::string* patterns[4] = {&flags.input, &flags.output, &flags.compare, &flags.png};
    for (int k = 0; k < 4; ++k) {
        if (patterns[k]->empty()) {
            lists[k].assign(frames.size(), "");
            continue;
        }
        auto files = frame_files(*patterns[k], frames);
        if (!files.ok()) return fail(files.error, 2);
        lists[k] = files.value;
    }
    for (size_t f = 0; f < frames.size(); ++f) {
        opt.progress = terminal_progress("apply frame " + std::to_string(frames[f]));
        if (const int status = run_frame(flags, opt, lists[0][f], lists[1][f], lists[2][f], lists[3][f]); status != 0)
            return status;
    }
    return 0;
}

}  // namespace

void add_apply_command(CLI::App& app, int& status) {
    auto f = std::make_shared<ApplyFlags>();
    CLI::App* cmd = app.add_subcommand("apply", "Diffract a render (RGB radiance + depth) through a real pinhole");
    cmd->add_option("input", f->input, "Input EXR: linear RGB radiance and depth")->required();
    cmd->add_option("-o,--output", f->output, "Output EXR (float RGB + the depth channel)")->required();
    for (const auto& [key, help] : front::setting_keys()) {
        if (key == "jitter" || key == "vignetting") continue;  // flags below
        if (key == "monochrome") {
            cmd->add_flag_callback("--monochrome", [f] { f->given["monochrome"] = "true"; }, help);
            continue;
        }
        cmd->add_option_function<std::string>("--" + key, [f, key = key](const std::string& v) { f->given[key] = v; },
                                              help)
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    }
    cmd->add_flag("--no-jitter", f->no_jitter, "Keep each source at its pixel centre");
    cmd->add_flag("--no-vignetting", f->no_vignetting, "Divide out the natural cos^4 fall-off");
    cmd->add_option("--compare", f->compare, "Write input | output | difference as a PNG through the display view");
    cmd->add_option("--png", f->png, "Also write the output as a display-referred PNG");
    cmd->add_option("--frames", f->frames,
                    "Frame range, e.g. 1-100; input, -o, --compare and --png are then patterns (#, @ or %04d)");
    cmd->add_option("--threads", f->threads, "Threads (0 = every core)")->capture_default_str();
    cmd->callback([f, &status] { status = run(*f); });
}

}  // namespace wavecam::cli
