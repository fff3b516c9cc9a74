// wavecam: the command line front over core.
#include <CLI/CLI.hpp>

#include "commands.h"
#include "terminal_progress.h"

int main(int argc, char** argv) {
    CLI::App app{"wavecam: a wave-optics pinhole camera"};
    app.require_subcommand(1);
    int status = 0;
    wavecam::cli::add_psf_command(app, status);
    wavecam::cli::add_apply_command(app, status);
    wavecam::cli::add_sweep_command(app, status);
    wavecam::cli::add_merge_command(app, status);
    wavecam::cli::add_farm_command(app, status);
    wavecam::cli::install_interrupt_handlers();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    return status;
}
