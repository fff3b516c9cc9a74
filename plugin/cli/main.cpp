// wavecam: the command line front over core.
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>

#include "commands.h"
#include "parse_errors.h"
#include "terminal_progress.h"
#include "wavecam/atomic_write.h"

namespace {

// What an exception says, in one line; std::bad_alloc as what it means.
std::string describe(const std::exception& e) {
    if (dynamic_cast<const std::bad_alloc*>(&e))
        return "out of memory (a job larger than this machine; lower the image size, --wavelengths or --runs, "
               "or lower --max-memory so that such jobs are refused before the work)";
    return e.what();
}

// The last line of defence: an exception thrown where nothing can catch it (inside a parallel
// loop) ends the run with a message and exit status 1, never SIGABRT; no temporary is left.
[[noreturn]] void on_terminate() {
    std::string what = "unexpected failure";
    if (std::exception_ptr e = std::current_exception()) try {
            std::rethrow_exception(e);
        } catch (const std::exception& x) {
            what = describe(x);
        } catch (...) {
        }
    if (const char* temp = wavecam::temporary_being_written()) ::unlink(temp);
    std::fprintf(stderr, "\nwavecam: %s\n", what.c_str());
    std::fflush(stderr);
    std::_Exit(1);
}

}  // namespace

int main(int argc, char** argv) {
    std::set_terminate(on_terminate);
    CLI::App app{"wavecam: a wave-optics pinhole camera"};
    app.require_subcommand(1);
    app.set_version_flag("--version", std::string("wavecam ") + WAVECAM_VERSION, "Print the version and exit");
    int status = 0;
    try {
        wavecam::cli::add_psf_command(app, status);
        wavecam::cli::add_apply_command(app, status);
        wavecam::cli::add_estimate_command(app, status);
        wavecam::cli::add_sweep_command(app, status);
        wavecam::cli::add_merge_command(app, status);
        wavecam::cli::add_farm_command(app, status);
        wavecam::cli::install_interrupt_handlers();
        if (const std::string twice = wavecam::cli::repeated_option(app, argc, argv); !twice.empty()) {
            std::fprintf(stderr, "%s\n", twice.c_str());
            return 2;
        }
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        std::fprintf(stderr, "%s\n", wavecam::cli::word_parse_error(app, e, argc, argv).c_str());
        return 2;
    } catch (const std::exception& e) {  // no exception leaves main: each command's failure, in words
        wavecam::cli::finish_progress();
        const std::string command = app.get_subcommands().empty() ? "" : app.get_subcommands().front()->get_name() + ": ";
        std::fprintf(stderr, "wavecam %s%s\n", command.c_str(), describe(e).c_str());
        return wavecam::cli::interrupted() ? wavecam::cli::interrupted_status() : 1;
    }
    return status;
}
