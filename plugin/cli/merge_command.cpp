// `wavecam merge SHARES... -o OUT`: the shares of a scene-sum job (`wavecam apply --share K/N`) into
// the image the single-machine run makes. A set that is not exactly one whole job is refused,
// one line per problem, and nothing is written.
#include <glob.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/strutil.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "commands.h"
#include "compare_sheet.h"
#include "output_paths.h"
#include "terminal_progress.h"
#include "wavecam/atomic_write.h"
#include "wavecam/output_layout.h"
#include "wavecam/share_files.h"
#include "../front/settings.h"

namespace wavecam::cli {
namespace {

struct MergeFlags {
    std::vector<std::string> shares;
    std::string output, compare, png;
};

int refuse(const std::vector<std::string>& problems, int status = 1) {
    std::fprintf(stderr, "wavecam merge: refused, nothing written:\n");
    for (const auto& p : problems) std::fprintf(stderr, "  %s\n", p.c_str());
    return status == 1 && interrupted() ? interrupted_status() : status;  // (a write refused at a signal)
}

// Arguments as given; one that is not a file but a pattern ("share-*-of-8.exr") is expanded.
std::vector<std::string> expand(const std::vector<std::string>& args, std::vector<std::string>& problems) {
    std::vector<std::string> files;
    for (const auto& a : args) {
        if (std::filesystem::exists(a) || a.find_first_of("*?[") == std::string::npos) {
            files.push_back(a);
            continue;
        }
        glob_t g{};
        if (::glob(a.c_str(), 0, nullptr, &g) == 0)
            for (size_t i = 0; i < g.gl_pathc; ++i) files.push_back(g.gl_pathv[i]);
        else
            problems.push_back(a + ": no share files match this pattern");
        ::globfree(&g);
    }
    return files;
}

// No output may be a share file, the shares' render or mask, or another output ("" when none is).
std::string check_paths(const MergeFlags& flags, const std::vector<std::string>& files, const std::string& render,
                        const std::string& aperture) {
    std::vector<PathUse> reads{{render, "the shares' render"}, {aperture_mask_file(aperture), "the shares' mask"}};
    for (const auto& f : files) reads.push_back({f, "the share file"});
    return path_conflict(reads, {{flags.output, "-o"}, {flags.compare, "--compare"}, {flags.png, "--png"}});
}

int run(const MergeFlags& flags) {
    std::vector<std::string> problems;
    std::vector<ShareFile> shares;
    const std::vector<std::string> files = expand(flags.shares, problems);
    for (const std::string* name : {&flags.output, &flags.compare, &flags.png})
        if (!name->empty())
            if (const std::string bad = output_name_problem(*name); !bad.empty()) return refuse({bad}, 2);
    if (const std::string clash = check_paths(flags, files, "", ""); !clash.empty()) return refuse({clash}, 2);
    for (const auto& f : files) {
        auto p = read_share(f);
        if (p.ok() && p.value.old_spelling) front::show_notes({kOldShareRecordNote});
        if (p.ok()) shares.push_back(std::move(p.value));
        else problems.push_back(p.error);
    }
    if (!shares.empty())
        if (auto set = check_share_set(shares); !set.ok())
            for (const auto& line : OIIO::Strutil::splits(set.error, "\n")) problems.push_back(line);
    if (shares.empty() && problems.empty()) problems.push_back("no share files given");
    if (!problems.empty()) return refuse(problems);

    const ShareFile& first = shares.front();
    const auto aperture = first.settings.find("aperture");
    if (const std::string clash =
            check_paths(flags, files, first.input, aperture == first.settings.end() ? "" : aperture->second);
        !clash.empty())
        return refuse({clash}, 2);
    auto fingerprint = file_fingerprint(first.input);
    if (!fingerprint.ok()) return refuse({fingerprint.error + " (the shares' input; the merge reads it again)"});
    if (fingerprint.value != first.input_fingerprint)
        return refuse({first.input + ": changed since the shares were computed (fingerprint " + fingerprint.value +
                       ", the shares' " + first.input_fingerprint + ")"});
    // the shares' settings resolved over the input's metadata, as `apply --share` resolved them
    auto in = read_and_resolve(first.input, first.settings);
    if (!in.ok()) return refuse({first.path + ": " + in.error});
    const OIIO::ImageBuf& src = in.value.image;
    DiffractOptions opt = in.value.settings.options;
    opt.max_terms = INFINITY;  // nothing is propagated: the shares hold the sums
    opt.scene_sum_propagator = stored_units(shares);
    OIIO::ImageBuf dst;
    if (auto r = DiffractPlan(opt).diffract(dst, src, first.input); !r.ok())
        return refuse({front::word_failure(r, front::Front::Command)});
    dst.specmod().attribute("wavecam.job", first.job);  // the job the shares belong to (farm status)
    auto written = write_plate(dst, src, flags.output, opt.pixel_type, opt.half_overflow, opt.max_memory);
    if (!written.ok()) return refuse({written.error});
    if (!written.value.empty()) std::fprintf(stderr, "wavecam merge: %s: %s\n", flags.output.c_str(), written.value.c_str());
    if (!flags.compare.empty())
        if (auto w = write_compare_sheet(src, dst, opt, flags.compare); !w.ok()) return refuse({w.error});
    if (!flags.png.empty())
        if (auto w = write_display_image(dst, opt, flags.png); !w.ok()) return refuse({w.error});
    std::printf("merged %zu shares: %s\nwrote %s\n", shares.size(),
                dst.spec().get_string_attribute("wavecam.summary").c_str(), flags.output.c_str());
    return 0;
}

}  // namespace

void add_merge_command(CLI::App& app, int& status) {
    auto f = std::make_shared<MergeFlags>();
    CLI::App* cmd = app.add_subcommand("merge", "Merge the share files of `wavecam apply --share K/N` into the image");
    cmd->add_option("shares", f->shares, "Share files or a pattern, e.g. 'share-*-of-8.exr'")->required();
    cmd->add_option("-o,--output", f->output, "Output EXR, as `wavecam apply` writes it")->required();
    cmd->add_option("--compare", f->compare, "Write input | output | difference as a PNG through the display view");
    cmd->add_option("--png", f->png, "Also write the output as a display-referred PNG");
    cmd->callback([f, &status] { status = run(*f); });
}

}  // namespace wavecam::cli
