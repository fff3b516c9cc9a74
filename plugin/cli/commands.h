// The `wavecam` subcommands. Each registers its flags on the app and, when chosen, runs and
// leaves its exit status in `status`.
#pragma once
#include <CLI/CLI.hpp>

namespace wavecam::cli {

void add_psf_command(CLI::App& app, int& status);
void add_apply_command(CLI::App& app, int& status);
void add_sweep_command(CLI::App& app, int& status);

}  // namespace wavecam::cli
