// The command line's own mistakes in our words: an option given twice is refused before it is
// parsed (every option, every command), and CLI11's parse errors are reworded to name the
// option at fault and what it expects. Both exit 2.
#pragma once
#include <CLI/CLI.hpp>

#include <string>

namespace wavecam::cli {

// "" when no option is given twice; else "COMMAND: --pinhole given twice; give each option once".
std::string repeated_option(CLI::App& app, int argc, char** argv);

// A CLI11 parse error as one line of ours ("COMMAND: --pinhole 0.3 mm: a unit must follow its
// number without a space, e.g. --pinhole 0.3mm").
std::string word_parse_error(CLI::App& app, const CLI::ParseError& e, int argc, char** argv);

}  // namespace wavecam::cli
