// `wavecam farm`: a scene-sum job on a Slurm cluster. `submit` writes an sbatch job array (one task
// per frame x share, each `wavecam apply --share K/N`) and one merge job per frame that waits for
// that frame's tasks (--dependency=afterok), skipping shares whose share files are complete;
// `status` says what is done. Files live in OUT.farm/: shares/FRAME/share-K-of-N.exr, logs/, the
// scripts and job.txt (what was submitted). The convolution method needs no shares: its frames go
// through the array in chunks, one `wavecam apply --frames` per task.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <thread>

#include "commands.h"
#include "output_paths.h"
#include "slurm.h"
#include "terminal_progress.h"
#include "wavecam/atomic_write.h"
#include "wavecam/diffract_image.h"
#include "wavecam/render_input.h"
#include "wavecam/share_files.h"
#include "wavecam/term_rate.h"
#include "../front/estimate_line.h"

namespace wavecam::cli {
namespace {
namespace fs = std::filesystem;

struct FarmFlags {
    std::string input, output, frames, partition;
    front::Settings given;  // the setting options; --no-jitter, --no-vignetting as jitter, vignetting = false
    bool wait = false, hold = false;
    int tasks = 0, cpus = 1;
};

int fail(const std::string& message, int status = 1) {
    std::fprintf(stderr, "wavecam farm: %s\n", message.c_str());
    return status;
}

std::string absolute(const std::string& p) { return fs::absolute(p).lexically_normal().string(); }

// OUT.farm, with the frame-number characters of a pattern made plain ("out.#.exr" -> "out._.exr.farm").
fs::path farm_dir(const std::string& output) {
    std::string name = fs::path(absolute(output)).filename().string();
    for (char& c : name)
        if (c == '#' || c == '@' || c == '%') c = '_';
    return fs::path(absolute(output)).parent_path() / (name + ".farm");
}

// One frame of the job (the frame number 0 and tag "image" for a single image).
struct Frame {
    int number = 0;
    std::string tag, input, output;
    std::string job;  // job fingerprint: input bytes and settings
};

fs::path share_path(const fs::path& farm, const Frame& f, int k, int n) {
    return farm / "shares" / f.tag / ("share-" + std::to_string(k) + "-of-" + std::to_string(n) + ".exr");
}

// A share file is complete when its header says it is this job's share K/N (it was written by
// rename, so a file that exists was written whole; the merge checks its pixels).
bool share_complete(const fs::path& path, const Frame& f, int k, int n) {
    if (!fs::exists(path)) return false;
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) return false;
    const OIIO::ImageSpec& spec = in->spec();
    bool old_spelling = false;
    const bool complete = share_record(spec, "job", &old_spelling) == f.job &&
                          share_record(spec, "", &old_spelling) == std::to_string(k) + "/" + std::to_string(n);
    if (old_spelling) front::show_notes({kOldShareRecordNote});
    return complete;
}

bool frame_merged(const Frame& f) {
    if (!fs::exists(f.output)) return false;
    auto in = OIIO::ImageInput::open(f.output);
    return in && in->spec().get_string_attribute("wavecam.job") == f.job;
}

std::string self_path() {
    std::error_code ec;
    const fs::path p = fs::read_symlink("/proc/self/exe", ec);
    return ec ? std::string("wavecam") : p.string();
}

// job.txt: key=value lines.
std::map<std::string, std::string> read_job_file(const fs::path& p) {
    std::map<std::string, std::string> kv;
    std::string text;
    OIIO::Filesystem::read_text_file(p.string(), text);
    for (const std::string& line : OIIO::Strutil::splits(text, "\n"))
        if (auto eq = line.find('='); eq != std::string::npos) kv[line.substr(0, eq)] = line.substr(eq + 1);
    return kv;
}

// The frames as job.txt lists them: "tag|number|input|output|job" per frame.
std::vector<Frame> frames_of(const std::map<std::string, std::string>& job) {
    std::vector<Frame> frames;
    for (int i = 0;; ++i) {
        auto it = job.find("frame." + std::to_string(i));
        if (it == job.end()) break;
        const auto f = OIIO::Strutil::splits(it->second, "|");
        if (f.size() == 5) frames.push_back({std::stoi(f[1]), f[0], f[2], f[3], f[4]});
    }
    return frames;
}

// What is done, frame by frame; exit status 0 when every frame is merged.
int report_status(const std::string& output) {
    const fs::path farm = farm_dir(output);
    if (!fs::exists(farm / "job.txt"))
        return fail(output + ": no farm job here (" + (farm / "job.txt").string() +
                    " is missing); submit one with `wavecam farm submit`");
    auto job = read_job_file(farm / "job.txt");
    const int n = std::atoi(job["tasks"].c_str());
    const auto states = squeue_states();
    // a job's or array task's state in the queue; `absent` when it is not there or the queue is unknown
    auto state = [&states](const std::string& id, const std::string& absent) {
        auto it = states.value.find(id);
        return it == states.value.end() ? absent : it->second;
    };
    const std::string array = job["array-job"];
    int merged = 0;
    const auto frames = frames_of(job);
    for (size_t i = 0; i < frames.size(); ++i) {
        const Frame& f = frames[i];
        std::string line = (f.tag == "image" ? "image" : "frame " + f.tag) + ": ";
        if (frame_merged(f)) {
            line += (n == 0 ? "done -> " : "merged -> ") + f.output;
            ++merged;
        } else if (n == 0) {  // convolution method: the frame's chunk task
            const std::string task = array + "_" + job["task-of." + std::to_string(i)];
            line += "not done; task " + task + " " + state(task, "not queued");
        } else {
            int done = 0;
            std::string queued;  // the missing shares
            for (int k = 1; k <= n; ++k)
                if (share_complete(share_path(farm, f, k, n), f, k, n)) ++done;
                else
                    queued += (queued.empty() ? "" : ", ") + std::to_string(k) + " " +
                              state(array + "_" + std::to_string(i * n + k - 1), "not queued");
            line += std::to_string(done) + " of " + std::to_string(n) + " shares done";
            if (!queued.empty()) line += "; missing: " + queued;
            const std::string merge_id = job["merge-job." + std::to_string(i)];
            if (const std::string merge_state = state(merge_id, ""); !merge_state.empty())
                line += "; merge job " + merge_id + " " + merge_state;
            else if (queued.empty())
                line += "; ready to merge";
            else
                line += "; re-submit to run the missing shares";
        }
        std::printf("%s\n", line.c_str());
    }
    if (!states.ok()) std::printf("(queue unknown: %s)\n", states.error.c_str());
    std::printf("%d of %zu frames %s\n", merged, frames.size(), n == 0 ? "done" : "merged");
    return merged == int(frames.size()) ? 0 : 1;
}

// Waits until none of `jobs` is in the queue, then reports; exit status 0 when all is done.
int wait_and_report(const FarmFlags& flags, const std::vector<std::string>& jobs) {
    for (;;) {
        auto now = squeue_states();
        if (!now.ok()) return fail(now.error);
        bool any = false;
        for (const auto& [id, state] : now.value)
            for (const auto& w : jobs) any |= id.substr(0, id.find('_')) == w;
        if (!any || interrupted()) break;
        std::this_thread::sleep_for(std::chrono::seconds(1));
    }
    return report_status(flags.output);
}

// A submission of this farm folder still in the queue (it would compute the same work twice).
Result<bool> check_nothing_queued(const FarmFlags& flags, size_t frames) {
    auto previous = read_job_file(farm_dir(flags.output) / "job.txt");
    auto states = squeue_states();
    if (!states.ok()) return Result<bool>::failure(states.error);
    for (const auto& [id, state] : states.value) {
        const std::string job = id.substr(0, id.find('_'));
        bool ours = job == previous["array-job"];
        for (size_t i = 0; i < frames; ++i) ours |= job == previous["merge-job." + std::to_string(i)];
        if (ours && !job.empty())
            return Result<bool>::failure("job " + id + " of the last submission is still " + state +
                                         "; wait for it (wavecam farm status " + flags.output +
                                         ") or scancel it, then submit again");
    }
    return Result<bool>::success(true);
}

// A task's `wavecam apply INPUT -o OUTPUT` with `share` (" --share K/N" or ""), its threads and the settings given.
std::string apply_command(const FarmFlags& flags, const std::string& input, const std::string& output,
                          const std::string& share) {
    std::string cmd = shell_quote(self_path()) + " apply " + shell_quote(input) + " -o " + shell_quote(output) + share +
                      " --threads " + std::to_string(flags.cpus);
    for (const auto& [key, value] : flags.given)
        if (key == "monochrome" || key == "diffract-again") cmd += " --" + key;
        else if (key != "jitter" && key != "vignetting") cmd += " --" + key + " " + shell_quote(value);
    if (flags.given.count("jitter")) cmd += " --no-jitter";
    if (flags.given.count("vignetting")) cmd += " --no-vignetting";
    return cmd;
}

// Writes the array script (`what` it does, then `cases`, one a task) and submits its tasks
// `indices` ("0-3", "0,2,5"; "": none, nothing submitted); the array's Slurm id, "" when none.
Result<std::string> submit_array(const fs::path& farm, const FarmFlags& flags, const std::string& what,
                                 const std::string& cases, const std::string& indices) {
    std::error_code ec;
    fs::create_directories(farm / "logs", ec);
    const std::string script =
        "#!/bin/bash\n# wavecam farm: " + what + "; written by `wavecam farm submit`.\n#SBATCH --job-name=wavecam\n" +
        "#SBATCH --output=" + (farm / "logs" / "task-%a.log").string() + "\n#SBATCH --cpus-per-task=" +
        std::to_string(flags.cpus) + "\ncase \"$SLURM_ARRAY_TASK_ID\" in\n" + cases +
        "*) echo \"wavecam farm: no task $SLURM_ARRAY_TASK_ID\" >&2; exit 1 ;;\nesac\n";
    if (auto w = write_text_atomically(script, farm / "array.sbatch"); !w.ok())
        return Result<std::string>::failure(w);
    if (indices.empty()) return Result<std::string>::success("");
    std::vector<std::string> opts{"--array=" + indices};
    if (!flags.partition.empty()) opts.push_back("--partition=" + flags.partition);
    if (flags.hold) opts.push_back("--hold");
    return sbatch((farm / "array.sbatch").string(), opts);
}

// The array job submitted: its id ("" when none was) and the tasks a frame it was split into
// (0: the convolution method's chunks of whole frames).
struct ArraySubmission {
    int tasks;
    const std::string& id;
};

// Each frame's entry under `key` in job.txt (its merge job, or the convolution method's task);
// "" where a frame has none.
struct FrameEntries {
    const std::string& key;
    const std::vector<std::string>& entry;
};

// Records the submission in job.txt: its head, then a line a frame, each followed by its entry
// where it has one. Then, with --wait, waits for the array and `merge_jobs` and reports.
int record_and_wait(const fs::path& farm, const FarmFlags& flags, const ArraySubmission& array,
                    const std::vector<Frame>& frames, const FrameEntries& entries,
                    std::vector<std::string> merge_jobs) {
    const int tasks = array.tasks;
    const std::string& array_id = array.id;
    const std::string& key = entries.key;
    const std::vector<std::string>& entry = entries.entry;
    std::ostringstream record;
    record << "input=" << absolute(flags.input) << "\noutput=" << absolute(flags.output) << "\ntasks=" << tasks
           << "\narray-job=" << array_id << "\n";
    for (size_t i = 0; i < frames.size(); ++i) {
        const Frame& f = frames[i];
        record << "frame." << i << "=" << f.tag << "|" << f.number << "|" << f.input << "|" << f.output << "|" << f.job
               << "\n";
        if (!entry[i].empty()) record << key << "." << i << "=" << entry[i] << "\n";
    }
    if (auto w = write_text_atomically(record.str(), farm / "job.txt"); !w.ok()) return fail(w.error);
    if (!flags.wait) return 0;
    if (!array_id.empty()) merge_jobs.push_back(array_id);
    return wait_and_report(flags, merge_jobs);
}

// The convolution method: the frames not yet made, in --tasks contiguous chunks of one array.
int submit_fast(const FarmFlags& flags, const front::Settings& settings, std::vector<Frame>& frames) {
    std::vector<size_t> todo;
    for (size_t i = 0; i < frames.size(); ++i) {
        auto fingerprint = file_fingerprint(frames[i].input);
        if (!fingerprint.ok()) return fail(fingerprint.error);
        frames[i].job = job_fingerprint(fingerprint.value, settings);
        if (!frame_merged(frames[i])) todo.push_back(i);
    }
    const size_t tasks = std::min(todo.size(), size_t(flags.tasks));
    std::printf("farm: %zu frame%s, convolution method (seconds to minutes a frame); %zu to make in %zu task%s\n",
                frames.size(), frames.size() == 1 ? "" : "s", todo.size(), tasks, tasks == 1 ? "" : "s");
    std::fflush(stdout);
    if (auto q = check_nothing_queued(flags, frames.size()); !q.ok()) return fail(q.error);
    const fs::path farm = farm_dir(flags.output);
    std::ostringstream cases;
    std::vector<std::string> task_of(frames.size());
    for (size_t t = 0; t < tasks; ++t) {
        std::string list;
        for (size_t c = t * todo.size() / tasks; c < (t + 1) * todo.size() / tasks; ++c) {
            list += (list.empty() ? "" : ",") + std::to_string(frames[todo[c]].number);
            task_of[todo[c]] = std::to_string(t);
        }
        cases << t << ") exec " << apply_command(flags, absolute(flags.input), absolute(flags.output), "")
              << (flags.frames.empty() ? "" : " --frames " + list) << " ;;\n";
    }
    auto id = submit_array(farm, flags, "convolution method, task i makes one chunk of frames", cases.str(),
                           tasks > 0 ? "0-" + std::to_string(tasks - 1) : "");
    if (!id.ok()) return fail(id.error);
    if (tasks > 0) std::printf("farm: submitted array job %s: %zu tasks\n", id.value.c_str(), tasks);
    else std::printf("farm: every frame is made; nothing to compute\n");
    return record_and_wait(farm, flags, {0, id.value}, frames, {"task-of", task_of}, {});
}

// The frames: one image, or a range of patterns.
Result<std::vector<Frame>> frame_list(const FarmFlags& flags) {
    using R = Result<std::vector<Frame>>;
    if (flags.frames.empty()) return R::success({{0, "image", absolute(flags.input), absolute(flags.output), {}}});
    auto listed = frame_numbers(flags.frames);
    if (!listed.ok()) return R::failure(listed);
    const std::vector<int>& numbers = listed.value;
    auto in = frame_files(flags.input, numbers);
    if (!in.ok()) return R::failure(in);
    auto out = frame_files(flags.output, numbers);
    if (!out.ok()) return R::failure(out);
    std::vector<Frame> frames;
    for (size_t i = 0; i < numbers.size(); ++i)
        frames.push_back({numbers[i], OIIO::Strutil::sprintf("%04d", numbers[i]), absolute(in.value[i]),
                          absolute(out.value[i]), {}});
    return R::success(std::move(frames));
}

// One frame's merge job, after its pending shares (`after`, array task indices); its Slurm id.
Result<std::string> submit_merge(const fs::path& farm, const Frame& f, int n, std::vector<std::string> opts,
                                 const std::vector<int>& after, const std::string& array_id) {
    const fs::path script = farm / ("merge-" + f.tag + ".sbatch");
    std::ostringstream merge;
    merge << "#!/bin/bash\n# wavecam farm: merges frame " << f.tag << "'s shares; written by `wavecam farm submit`.\n"
          << "#SBATCH --job-name=wavecam-merge\n"
          << "#SBATCH --output=" << (farm / "logs" / ("merge-" + f.tag + ".log")).string() << "\n"
          << "exec " << shell_quote(self_path()) << " merge "
          << shell_quote((farm / "shares" / f.tag / ("share-*-of-" + std::to_string(n) + ".exr")).string())
          << " -o " << shell_quote(f.output) << "\n";
    if (auto w = write_text_atomically(merge.str(), script); !w.ok()) return Result<std::string>::failure(w);
    if (!after.empty()) {
        std::string dep = "--dependency=afterok";
        for (int index : after) dep += ":" + array_id + "_" + std::to_string(index);
        opts.push_back(dep);
        opts.push_back("--kill-on-invalid-dep=yes");
    }
    return sbatch(script.string(), opts);
}

// The share array's cases: task i computes share (i % N) + 1 of frame i / N. Returns the tasks
// still to compute (neither merged nor complete), frame by frame.
std::vector<std::vector<int>> share_tasks(std::ostringstream& cases, const fs::path& farm, const FarmFlags& flags,
                                          const std::vector<Frame>& frames) {
    const int n = flags.tasks;
    std::error_code ec;
    std::vector<std::vector<int>> pending_of(frames.size());
    for (size_t i = 0; i < frames.size(); ++i) {
        const Frame& f = frames[i];
        fs::create_directories(farm / "shares" / f.tag, ec);
        const bool merged = frame_merged(f);
        for (int k = 1; k <= n; ++k) {
            const int index = int(i) * n + k - 1;
            const fs::path file = share_path(farm, f, k, n);
            const std::string share = " --share " + std::to_string(k) + "/" + std::to_string(n);
            cases << index << ") exec " << apply_command(flags, f.input, file.string(), share) << " ;;\n";
            if (!merged && !share_complete(file, f, k, n)) pending_of[i].push_back(index);
        }
    }
    return pending_of;
}

// Where a frame's output is an input, the mask or another frame's output: the clash in words, else "".
std::string frame_path_clash(const FarmFlags& flags, const std::vector<Frame>& frames) {
    std::vector<PathUse> reads, writes;
    if (auto a = flags.given.find("aperture"); a != flags.given.end())
        reads.push_back({aperture_mask_file(a->second), "the --aperture mask"});
    for (const Frame& f : frames) {
        const std::string tag = flags.frames.empty() ? "" : " (frame " + std::to_string(f.number) + ")";
        reads.push_back({f.input, "the render" + tag});
        writes.push_back({f.output, "-o" + tag});
    }
    return path_conflict(reads, writes);
}

// The whole farm's terms in core-hours at the rate of one core measured here, and its wall time
// with every task running at once.
void print_farm_estimate(const FarmFlags& flags, size_t frames, double total) {
    const double core_rate = measured_term_rate(1);
    const double core_hours = total / core_rate / 3600;
    std::printf("farm: %zu frame%s x %d shares = %.3g terms, about %.3g core-hours at the %.3g terms/s per core "
                "measured here; with every task running at once, about %s\n",
                frames, frames == 1 ? "" : "s", flags.tasks, total, core_hours, core_rate,
                front::format_duration(total / frames / flags.tasks / (core_rate * flags.cpus)).c_str());
    std::fflush(stdout);
}

int submit(const FarmFlags& flags) {
    if (flags.tasks < 1) return fail("--tasks: expected at least 1 share per frame", 2);
    if (flags.cpus < 1 || flags.cpus > 1024)
        return fail("--cpus-per-task: expected 1 to 1024 cores, got '" + std::to_string(flags.cpus) + "'", 2);
    const front::Settings settings = recorded_settings(flags.given);

    auto listed = frame_list(flags);
    if (!listed.ok()) return fail(listed.error, 2);
    std::vector<Frame>& frames = listed.value;
    if (const std::string clash = frame_path_clash(flags, frames); !clash.empty()) return fail(clash, 2);

    // The estimate, before anything is submitted: each frame's settings resolved as its task will.
    double total = 0;
    for (auto& f : frames) {
        auto in = read_and_resolve(f.input, flags.given);
        if (!in.ok()) return fail(in.error, 2);
        const DiffractOptions& opt = in.value.settings.options;
        if (opt.method == DiffractMethod::Convolution) {
            if (&f != &frames.front()) return fail(f.input + ": method convolution, unlike the first frame's", 2);
            return submit_fast(flags, settings, frames);
        }
        auto render = load_render(in.value.image, f.input, opt.read);
        if (!render.ok()) return fail(front::word_failure(Result<bool>::failure(render), front::Front::Command));
        const PinholeCamera camera = render.value.camera(opt.film_distance);
        const double terms = estimate_terms(opt, camera, render.value.depth, render.value.colour);
        const int wavelengths = opt.wavelengths.empty() ? opt.wavelength_count : int(opt.wavelengths.size());
        const int runs = job_runs(opt, camera, render.value.depth, render.value.colour);
        if (auto s = work_share(flags.tasks, flags.tasks, wavelengths, runs, camera.height); !s.ok())
            return fail(f.input + ": --tasks: " + s.error, 2);
        if (terms / flags.tasks > opt.max_terms) {
            std::ostringstream m;
            m << f.input << ": a share is about " << terms / flags.tasks << " terms (" << terms << " / " << flags.tasks
              << "), beyond --max-terms; use more --tasks or raise --max-terms (now " << opt.max_terms << ")";
            return fail(m.str(), 2);
        }
        auto fingerprint = file_fingerprint(f.input);
        if (!fingerprint.ok()) return fail(fingerprint.error);
        f.job = job_fingerprint(fingerprint.value, settings);
        if (&f == &frames.front())
            std::printf("farm: %dx%d pixels x %d wavelengths x %d runs = %.3g terms a frame\n", camera.width,
                        camera.height, wavelengths, runs, terms);
        total += terms;
    }
    print_farm_estimate(flags, frames.size(), total);

    if (auto q = check_nothing_queued(flags, frames.size()); !q.ok()) return fail(q.error);
    const fs::path farm = farm_dir(flags.output);

    // The array: every (frame, share) task in the script, only the incomplete ones submitted.
    const int n = flags.tasks;
    std::ostringstream cases;
    const std::vector<std::vector<int>> pending_of = share_tasks(cases, farm, flags, frames);
    std::vector<int> pending;
    for (const auto& p : pending_of) pending.insert(pending.end(), p.begin(), p.end());
    const std::string what =
        "task i computes share (i % " + std::to_string(n) + ") + 1 of frame i / " + std::to_string(n);
    auto submitted = submit_array(farm, flags, what, cases.str(), index_list(pending));
    if (!submitted.ok()) return fail(submitted.error);
    const std::string array_id = submitted.value;
    std::vector<std::string> common;
    if (!flags.partition.empty()) common.push_back("--partition=" + flags.partition);
    if (!pending.empty())
        std::printf("farm: submitted array job %s: %zu of %zu tasks (the others are complete)\n", array_id.c_str(),
                    pending.size(), frames.size() * n);
    else
        std::printf("farm: every share is complete; nothing to compute\n");

    std::vector<std::string> merge_job(frames.size()), waiting;
    for (size_t i = 0; i < frames.size(); ++i) {
        const Frame& f = frames[i];
        if (frame_merged(f)) continue;
        auto id = submit_merge(farm, f, n, common, pending_of[i], array_id);
        if (!id.ok()) return fail(id.error);
        merge_job[i] = id.value;
        waiting.push_back(id.value);
        std::printf("farm: %s%s: merge job %s\n", f.tag == "image" ? "" : "frame ", f.tag.c_str(), id.value.c_str());
    }
    return record_and_wait(farm, flags, {n, array_id}, frames, {"merge-job", merge_job}, waiting);
}

}  // namespace

void add_farm_command(CLI::App& app, int& status) {
    CLI::App* farm = app.add_subcommand("farm", "Run a scene-sum job on a Slurm cluster: shares, then a merge per frame");
    farm->require_subcommand(1);
    auto f = std::make_shared<FarmFlags>();
    CLI::App* cmd = farm->add_subcommand("submit", "Submit the job array and the merge jobs (sbatch on PATH)");
    cmd->add_option("input", f->input, "Input EXR (or a pattern with --frames)")->required();
    cmd->add_option("-o,--output", f->output, "Output EXR (or a pattern with --frames)")->required();
    add_setting_options(cmd, f->given);
    cmd->add_option("--tasks", f->tasks, "Scene-sum methods: shares per frame (array tasks per frame); convolution method: tasks in all, each a chunk of frames")->required();
    cmd->add_option("--frames", f->frames, "Frame range, e.g. 1-100; input and -o are then patterns (#, @, %04d)");
    cmd->add_option("--partition", f->partition, "Slurm partition");
    cmd->add_option("--cpus-per-task", f->cpus, "Cores per task (its threads)")->capture_default_str();
    cmd->add_flag("--hold", f->hold, "Submit the array held (release it with scontrol release JOBID)");
    cmd->add_flag("--wait", f->wait, "Wait until the jobs leave the queue, then print the status");
    cmd->callback([f, &status] { status = submit(*f); });

    auto out = std::make_shared<std::string>();
    CLI::App* st = farm->add_subcommand("status", "What is done: merged frames, complete shares, queued tasks");
    st->add_option("output", *out, "The -o given to submit")->required();
    st->callback([out, &status] { status = report_status(*out); });
}

}  // namespace wavecam::cli
