#include "parse_errors.h"

#include <cctype>
#include <cstdlib>
#include <map>
#include <vector>

namespace wavecam::cli {
namespace {

// The (sub)command argv names, deepest first found: "wavecam farm submit ..." -> farm submit.
CLI::App* command_of(CLI::App& app, int argc, char** argv, std::string& name) {
    CLI::App* at = &app;
    name = "wavecam";
    for (int i = 1; i < argc; ++i) {
        CLI::App* sub = nullptr;
        for (CLI::App* s : at->get_subcommands({}))
            if (s->get_name() == argv[i]) sub = s;
        if (!sub) break;
        at = sub;
        name += " " + sub->get_name();
    }
    return at;
}

bool is_number(const std::string& s) {
    char* end = nullptr;
    std::strtod(s.c_str(), &end);
    return !s.empty() && *end == '\0';
}

bool is_word(const std::string& s) {
    if (s.empty()) return false;
    for (char c : s)
        if (!std::isalpha(static_cast<unsigned char>(c)) && c != '%') return false;
    return true;
}

// What follows CLI11's "... : " in its message ("The following argument was not expected: mm").
std::string after_colon(const std::string& what) {
    const size_t at = what.rfind(": ");
    return at == std::string::npos ? what : what.substr(at + 2);
}

}  // namespace

std::string repeated_option(CLI::App& app, int argc, char** argv) {
    std::string name;
    CLI::App* cmd = command_of(app, argc, argv, name);
    std::map<std::string, const CLI::Option*> by_name;
    for (const CLI::Option* opt : cmd->get_options()) {
        if (!opt->nonpositional()) continue;
        for (const auto& l : opt->get_lnames()) by_name["--" + l] = opt;
        for (const auto& s : opt->get_snames()) by_name["-" + s] = opt;
    }
    std::map<const CLI::Option*, std::string> seen;
    for (int i = 1; i < argc; ++i) {
        std::string token = argv[i];
        if (token == "--") break;
        token = token.substr(0, token.find('='));
        auto it = by_name.find(token);
        if (it == by_name.end() || it->first == "--help" || it->first == "-h") continue;
        if (auto [was, fresh] = seen.emplace(it->second, token); !fresh)
            return name + ": " + (was->second == token ? token : was->second + " (" + token + ")") +
                   " given twice; give each option once";
    }
    return {};
}

std::string word_parse_error(CLI::App& app, const CLI::ParseError& e, int argc, char** argv) {
    std::string name;
    CLI::App* cmd = command_of(app, argc, argv, name);
    const std::string what = e.what(), help = " (`" + name + " --help` lists the options)";
    if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
        const std::string extras = after_colon(what), first = extras.substr(0, extras.find(' '));
        for (int i = 3; i < argc; ++i)
            if (first == argv[i] && is_word(first) && is_number(argv[i - 1]) && argv[i - 2][0] == '-')
                return name + ": " + argv[i - 2] + " " + argv[i - 1] + " " + first +
                       ": a unit must follow its number without a space, e.g. " + argv[i - 2] + " " + argv[i - 1] +
                       first;
        return name + ": '" + extras + "' was not expected: not an option of this command, nor an input it takes" +
               help;
    }
    if (dynamic_cast<const CLI::ConversionError*>(&e)) {
        // "Could not convert: --threads = abc"
        const std::string rest = after_colon(what);
        const size_t eq = rest.find(" = ");
        if (eq != std::string::npos)
            return name + ": " + rest.substr(0, eq) + ": expected a whole number, got '" + rest.substr(eq + 3) + "'";
    }
    if (dynamic_cast<const CLI::RequiredError*>(&e)) {
        // "--output is required", "input is required", "A subcommand is required"
        const std::string option = what.substr(0, what.find(" is required"));
        if (what.find("subcommand") != std::string::npos) {
            std::string commands;
            for (const CLI::App* sub : cmd->get_subcommands({}))
                commands += (commands.empty() ? "" : ", ") + sub->get_name();
            return name + ": expected a command: " + commands + " (`" + name + " --help`)";
        }
        for (const CLI::Option* opt : cmd->get_options())
            if (opt->get_name() == option || "--" + opt->get_name() == option ||
                opt->get_name(false, true).find(option) != std::string::npos)
                return name + ": " + opt->get_name(false, true) + " is required" + help;
        return name + ": " + what;
    }
    if (dynamic_cast<const CLI::ArgumentMismatch*>(&e)) {
        // "--pinhole: 1 required TEXT missing"
        const std::string option = what.substr(0, what.find(':'));
        if (what.find("missing") != std::string::npos) return name + ": " + option + ": expected a value after it";
        return name + ": " + option + ": expected one value; give each option once";
    }
    return name + ": " + what + help;
}

}  // namespace wavecam::cli
