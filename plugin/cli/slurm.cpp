#include "slurm.h"

#include <cstdio>
#include <sstream>
#include <sys/wait.h>

namespace wavecam::cli {
namespace {

struct Captured {
    int status = -1;
    std::string output;  // stdout and stderr, without trailing newlines and spaces
};

Captured capture(const std::string& command) {
    Captured c;
    FILE* p = ::popen((command + " 2>&1").c_str(), "r");
    if (!p) return c;
    char buf[512];
    while (std::fgets(buf, sizeof buf, p)) c.output += buf;
    c.output.erase(c.output.find_last_not_of("\n ") + 1);
    const int s = ::pclose(p);
    c.status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
    return c;
}

}  // namespace

std::string shell_quote(const std::string& text) {
    std::string q = "'";
    for (char c : text) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

Result<std::string> sbatch(const std::string& script, const std::vector<std::string>& options) {
    std::string cmd = "sbatch --parsable";
    for (const auto& o : options) cmd += " " + shell_quote(o);
    const Captured c = capture(cmd + " " + shell_quote(script));
    // --parsable prints "JOBID" or "JOBID;CLUSTER"
    const std::string id = c.output.substr(0, c.output.find(';'));
    if (c.status != 0 || id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
        return Result<std::string>::failure("sbatch " + script + ": " + (c.output.empty() ? "failed" : c.output));
    return Result<std::string>::success(id);
}

Result<std::map<std::string, std::string>> squeue_states() {
    const Captured c = capture("squeue --noheader --array --format='%i %T'");
    if (c.status != 0)
        return Result<std::map<std::string, std::string>>::failure("squeue: " +
                                                                   (c.output.empty() ? "failed" : c.output));
    std::map<std::string, std::string> states;
    std::istringstream lines(c.output);
    std::string id, state;
    while (lines >> id >> state) states[id] = state;
    return Result<std::map<std::string, std::string>>::success(states);
}

std::string index_list(const std::vector<int>& ids) {
    std::string s;
    for (size_t a = 0; a < ids.size();) {
        size_t b = a;
        while (b + 1 < ids.size() && ids[b + 1] == ids[b] + 1) ++b;
        s += (s.empty() ? "" : ",") + std::to_string(ids[a]) + (b > a ? "-" + std::to_string(ids[b]) : "");
        a = b + 1;
    }
    return s;
}

}  // namespace wavecam::cli
