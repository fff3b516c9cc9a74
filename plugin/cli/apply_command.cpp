// `wavecam apply`: a render (RGB + depth EXR) in, the real pinhole camera's image out.
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
    std::string input, output, compare, png;
    front::Settings given;  // the settings flags that were given, by key
    bool no_vignetting = false, no_jitter = false;
    int threads = 0;
};

int fail(const std::string& message, int status = 1) {
    finish_progress();
    std::fprintf(stderr, "wavecam apply: %s\n", message.c_str());
    return status;
}

int run(const ApplyFlags& flags) {
    namespace fs = std::filesystem;
    front::Settings settings = flags.given;
    if (flags.no_vignetting) settings["vignetting"] = "false";
    if (flags.no_jitter) settings["jitter"] = "false";
    auto options = front::options_from_settings(settings);
    if (!options.ok()) return fail("--" + options.error, 2);
    std::error_code ec;
    if (fs::exists(flags.output) && fs::equivalent(flags.input, flags.output, ec))
        return fail(flags.output + ": the output would overwrite the input; choose another -o", 2);
    DiffractOptions opt = options.value;
    opt.progress = terminal_progress("apply");

    OIIO::ImageBuf src(flags.input);
    if (!src.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
        std::string e = src.geterror();
        return fail(flags.input + ": " + (e.empty() ? "cannot be read as an image" : e));
    }
    OIIO::ImageBuf dst;
    if (!diffract(dst, src, flags.input, opt, flags.threads))
        return fail(dst.geterror(), interrupted() ? 130 : 1);
    finish_progress();
    if (auto w = write_image_atomically(dst, flags.output, OIIO::TypeDesc::FLOAT); !w.ok()) return fail(w.error);
    if (!flags.compare.empty())
        if (auto w = write_compare_sheet(src, dst, opt, flags.compare); !w.ok()) return fail(w.error);
    if (!flags.png.empty())
        if (auto w = write_display_png(dst, opt, flags.png); !w.ok()) return fail(w.error);
    std::printf("pinhole %s, %s\n", dst.spec().get_string_attribute("wavecam.pinhole").c_str(),
                dst.spec().get_string_attribute("wavecam.summary").c_str());
    std::printf("wrote %s\n", flags.output.c_str());
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
        cmd->add_option_function<std::string>("--" + key, [f, key = key](const std::string& v) { f->given[key] = v; },
                                              help)
            ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    }
    cmd->add_flag("--no-jitter", f->no_jitter, "Keep each source at its pixel centre");
    cmd->add_flag("--no-vignetting", f->no_vignetting, "Divide out the natural cos^4 fall-off");
    cmd->add_option("--compare", f->compare, "Write input | output | difference as a PNG through the display view");
    cmd->add_option("--png", f->png, "Also write the output as a display-referred PNG");
    cmd->add_option("--threads", f->threads, "Threads (0 = every core)")->capture_default_str();
    cmd->callback([f, &status] { status = run(*f); });
}

}  // namespace wavecam::cli
