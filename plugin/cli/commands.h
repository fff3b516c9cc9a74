// The `wavecam` subcommands. Each registers its flags on the app and, when chosen, runs and
// leaves its exit status in `status`.
#pragma once
#include <CLI/CLI.hpp>
#include <OpenImageIO/imagebuf.h>

#include <string>
#include <vector>

#include "wavecam/result.h"
#include "../front/settings.h"

namespace wavecam::cli {

void add_psf_command(CLI::App& app, int& status);
void add_apply_command(CLI::App& app, int& status);
void add_estimate_command(CLI::App& app, int& status);
void add_sweep_command(CLI::App& app, int& status);
void add_merge_command(CLI::App& app, int& status);
void add_farm_command(CLI::App& app, int& status);

// --threads: 0 (every core) to 1024; errors read "threads: expected ...".
Result<int> parse_threads(int threads);

// --frames' numbers (OIIO's sequence syntax: "1-100", "1-100x2", "3,7,10-20"), counted before
// they are expanded: more than 100000 frames are refused, and so is any order but ascending, each
// frame once ("3-1", "1-10x-2", "5,2"). Errors name --frames.
Result<std::vector<int>> frame_numbers(const std::string& text);

// Frame numbers as ranges, for messages: {1, 2, 3, 7} -> "1-3,7"; "none" for none.
std::string frame_ranges(const std::vector<int>& frames);

// The files of a frame range: OIIO's own pattern rules ("shot.#.exr" = 4 digits, "@" = 1,
// "%04d" printf style) and sequence syntax ("1-100", "1-100x2", "3,7,10-20").
Result<std::vector<std::string>> frame_files(const std::string& pattern, const std::vector<int>& frames);

// The setting options apply and farm submit share, one per settings key (front/settings.h), each
// stored in `given` by its key: --monochrome, --no-jitter and --no-vignetting as flags
// (monochrome = true, jitter = false, vignetting = false).
void add_setting_options(CLI::App* cmd, front::Settings& given);

// The settings a share file records for its merge: every result-changing key as given (not the
// bounds --max-terms, --max-memory).
front::Settings recorded_settings(const front::Settings& given);

// A render read, and its settings resolved in the one order (front/settings.h): the source's
// wavecam.KEY metadata under `given`, the command's flags. Errors name the file.
struct ResolvedInput {
    OIIO::ImageBuf image;
    front::ResolvedSettings settings;
};
Result<ResolvedInput> read_and_resolve(const std::string& input, const front::Settings& given);

}  // namespace wavecam::cli
