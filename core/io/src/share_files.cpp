#include "wavecam/share_files.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <algorithm>
#include <memory>
#include <set>
#include <sstream>

#include "resolved_frame.h"
#include "wavecam/render_input.h"
#include "wavecam/spectrum.h"

namespace wavecam {
namespace {

// The share's records: wavecam.share ("K/N") and wavecam.share.NAME; wavecam.part.share and
// wavecam.part.NAME read as the same records.
constexpr const char* kShareRecord = "wavecam.share";
constexpr const char* kOldShareRecord = "wavecam.part.share";
constexpr const char* kRecordPrefix = "wavecam.share.";
constexpr const char* kOldRecordPrefix = "wavecam.part.";
constexpr const char* kSettingPrefix = "setting.";  // wavecam.share.setting.KEY: a setting as given

std::string record_name(const std::string& name) { return name.empty() ? kShareRecord : kRecordPrefix + name; }
std::string old_record_name(const std::string& name) {
    return name.empty() ? kOldShareRecord : kOldRecordPrefix + name;
}

const OIIO::ParamValue* find_record(const OIIO::ImageSpec& spec, const std::string& name, bool* old_spelling) {
    if (const OIIO::ParamValue* p = spec.find_attribute(record_name(name))) return p;
    const OIIO::ParamValue* p = spec.find_attribute(old_record_name(name));
    if (p && old_spelling) *old_spelling = true;
    return p;
}

int int_record(const OIIO::ImageSpec& spec, const std::string& name, bool* old_spelling, int absent = 0) {
    const OIIO::ParamValue* p = find_record(spec, name, old_spelling);
    return p ? p->get_int(absent) : absent;
}

// FNV-1a, 64 bit (Fowler, Noll, Vo): a fingerprint, not a cryptographic hash.
struct Fnv1a {
    uint64_t h = 1469598103934665603ull;
    void add(const void* data, size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    }
    std::string hex() const {
        char s[17];
        std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(h));
        return s;
    }
};

std::string channel_name(int w, int r, int sign) {
    char s[32];
    std::snprintf(s, sizeof s, "w%03d.r%03d.%s", w, r, sign > 0 ? "pos" : "neg");
    return s;
}

// Channel by channel in name order: OpenEXR stores channels sorted by name, whatever order
// they were written in.
std::string pixel_checksum(const OIIO::ImageBuf& image) {
    const size_t n = image.spec().image_pixels(), C = size_t(image.nchannels());
    std::vector<float> px(n * C);
    image.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());
    std::map<std::string, size_t> by_name;
    for (size_t c = 0; c < C; ++c) by_name[image.spec().channelnames[c]] = c;
    Fnv1a f;
    for (const auto& [name, c] : by_name) {
        f.add(name.data(), name.size());
        for (size_t p = 0; p < n; ++p) f.add(&px[p * C + c], sizeof(float));
    }
    return f.hex();
}

std::string range_text(int a, int b) { return std::to_string(a) + "-" + std::to_string(b); }

bool parse_range(const std::string& t, int& a, int& b) {
    int used = 0;
    return std::sscanf(t.c_str(), "%d-%d%n", &a, &b, &used) == 2 && used == int(t.size());
}

std::string share_name(const ShareFile& p) {
    return "share " + std::to_string(p.share.index) + "/" + std::to_string(p.share.count) + " (" + p.path + ")";
}

// The value most shares carry (the first share's on a tie), so the odd one out is named.
template <class Key>
Key majority(const std::vector<ShareFile>& shares, Key (*key)(const ShareFile&)) {
    std::map<Key, int> count;
    for (const auto& p : shares) ++count[key(p)];
    Key best = key(shares.front());
    for (const auto& [k, n] : count)
        if (n > count[best]) best = k;
    return best;
}

}  // namespace

Result<std::string> file_fingerprint(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Result<std::string>::failure(path + ": cannot be read");
    Fnv1a f;
    std::vector<char> buf(1 << 16);
    while (in.read(buf.data(), buf.size()) || in.gcount() > 0) f.add(buf.data(), size_t(in.gcount()));
    return Result<std::string>::success(f.hex());
}

std::string job_fingerprint(const std::string& input_fingerprint, const SettingsText& settings) {
    Fnv1a f;
    f.add(input_fingerprint.data(), input_fingerprint.size());
    for (const auto& [k, v] : settings) {
        const std::string line = "\n" + k + "=" + v;
        f.add(line.data(), line.size());
    }
    return f.hex();
}

namespace {

// One share resolved once: the frame (resolve_frame, as the run sees it), its units (unit u is
// wavelength u / R and run u % R, one propagation for colour and three, one per channel, for
// monochrome light: spectrum.h) and each unit's terms.
struct Share {
    detail::ResolvedFrame f;
    int S = 0, R = 1, per_wavelength = 1;  // wavelengths, runs, propagations per unit
    WorkShare sh;
    SceneSumSettings s;  // the frame's scene-sum settings, on the share's rows
    std::vector<double> unit_terms;
    double terms = 0;
    std::string fingerprint;
    std::string job;  // "share 2/8 of 24x16 pixels x 3 wavelengths x 2 runs: ..."
};

Result<Share> resolve_share(const OIIO::ImageBuf& src, const std::string& input_path, const DiffractOptions& opt,
                            int index, int count, int nthreads) {
    using R = Result<Share>;
    if (opt.method == DiffractMethod::Convolution)
        return R::failure(input_path +
                              ": shares are of the scene-sum methods' work; expected method random-phase or incoherent",
                          ErrorKind::Invalid, "method");
    auto input = load_render(src, input_path, opt.read);
    if (!input.ok()) return R::failure(input);
    auto frame = detail::resolve_frame(opt, std::move(input.value), input_path, nthreads);
    if (!frame.ok()) return R::failure(frame);
    Share j;
    j.f = std::move(frame.value);
    const std::vector<double>& wavelengths = j.f.colour.sampling.wavelength;
    j.S = int(wavelengths.size());
    j.per_wavelength = j.f.colour.basis.size() / j.S;
    j.R = opt.method == DiffractMethod::Incoherent ? 1 : j.f.scene_sum.runs;
    auto share = work_share(index, count, j.S, j.R, j.f.in.height);
    if (!share.ok()) return R::failure(share.error);
    j.sh = share.value;
    auto fingerprint = file_fingerprint(input_path);
    if (!fingerprint.ok()) return R::failure(fingerprint.error);
    j.fingerprint = fingerprint.value;
    j.s = j.f.scene_sum;
    j.s.row_begin = j.sh.row_begin;
    j.s.row_end = j.sh.row_end;
    for (int u = j.sh.unit_begin; u < j.sh.unit_end; ++u) {
        SceneSumSettings unit = j.s;
        unit.run_begin = u % j.R;
        unit.run_end = u % j.R + 1;
        j.unit_terms.push_back(j.per_wavelength * scene_terms(unit, j.f.device, j.f.camera, wavelengths[u / j.R]));
        j.terms += j.unit_terms.back();
    }
    std::ostringstream job;
    job << "share " << index << "/" << count << " of " << j.f.in.width << "x" << j.f.in.height << " pixels x " << j.S
        << " wavelengths x " << j.R << " runs, " << summation_word(j.s.summation) << " summation" << ": " << describe_share(j.sh, j.R);
    j.job = job.str();
    if (j.terms > opt.max_terms) {
        std::ostringstream m;
        m << input_path << ": " << j.job << " = " << j.terms << " terms, beyond the max-terms limit of "
          << opt.max_terms;
        return R::failure(m.str(), ErrorKind::TooLarge, "max-terms");
    }
    return R::success(std::move(j));
}

// Each unit of the share computed on its own into a zeroed image and kept by name; progress by
// each unit's share of the estimated terms.
MonochromePropagator unit_propagator(const Share& j, const ProgressFn& progress,
                                     std::map<std::string, std::vector<float>>& units, double& done) {
    // the runs of a wavelength share its kernel summation's kernels
    const RunPropagator run = run_propagator(j.s, j.f.device, j.f.report.get());
    return [&j, progress, &units, &done, run](const MonochromeScene& mono, double wavelength, float*,
                                              const ProgressFn&) {
        for (int r = 0; r < j.R; ++r) {
            const int u = mono.spectral_index / j.per_wavelength * j.R + r;
            if (u < j.sh.unit_begin || u >= j.sh.unit_end) continue;
            // A wavelength's negative power (rare) is not in the estimate: count it at no weight;
            // monochrome light's three channels share their unit's weight.
            const double weight = mono.sign > 0 ? j.unit_terms[u - j.sh.unit_begin] / j.terms / j.per_wavelength : 0;
            const double before = done;
            ProgressFn report;
            if (progress)
                report = [&progress, before, weight](double f) { return progress(std::min(1.0, before + weight * f)); };
            std::vector<float> irradiance(size_t(j.f.in.width) * j.f.in.height, 0.0f);
            if (auto rr = run(mono, wavelength, r, irradiance.data(), report); !rr.ok()) return rr;
            done += weight;
            units[channel_name(mono.spectral_index, r, mono.sign)] = std::move(irradiance);
        }
        return Result<bool>::success(true);
    };
}

// The share file's header: the whole job's (`spec`), its channels the units by name, its window the
// share's rows of the input (an overscan margin included: the merge crops it, as a single run
// does), and what was summed: share `share` of `job`.
OIIO::ImageSpec share_spec(OIIO::ImageSpec spec, const Share& j, const std::vector<std::string>& order,
                          const JobRecord& job, const WorkShare& share) {
    const std::string& input_path = job.input_path;
    const SettingsText& settings = job.settings;
    spec.nchannels = int(order.size());
    spec.channelnames = order;
    spec.alpha_channel = -1;
    spec.z_channel = -1;
    spec.x = spec.full_x = 0;
    spec.width = spec.full_width = j.f.in.width;
    spec.y = j.sh.row_begin;
    spec.height = j.sh.row_end - j.sh.row_begin;
    spec.full_y = 0;
    spec.full_height = j.f.in.height;
    spec.attribute(record_name(""), std::to_string(share.index) + "/" + std::to_string(share.count));
    spec.attribute(record_name("units"), range_text(j.sh.unit_begin, j.sh.unit_end));
    spec.attribute(record_name("rows"), range_text(j.sh.row_begin, j.sh.row_end));
    spec.attribute(record_name("summed"), describe_share(j.sh, j.R));
    spec.attribute(record_name("wavelength-count"), j.S);
    spec.attribute(record_name("runs"), j.R);
    spec.attribute(record_name("propagations"), j.per_wavelength);
    spec.attribute(record_name("terms"), float(j.terms));
    spec.attribute(record_name("input"), input_path);
    spec.attribute(record_name("input-fingerprint"), j.fingerprint);
    spec.attribute(record_name("job"), job_fingerprint(j.fingerprint, settings));
    spec.attribute(record_name("decision"), detail::decision_text(j.s));
    for (const auto& [k, v] : settings) spec.attribute(record_name(kSettingPrefix + k), v);
    return spec;
}

}  // namespace

std::string share_record(const OIIO::ImageSpec& spec, const std::string& name, bool* old_spelling) {
    const OIIO::ParamValue* p = find_record(spec, name, old_spelling);
    return p ? p->get_string() : std::string();
}

Result<bool> diffract_share(OIIO::ImageBuf& share_image, const OIIO::ImageBuf& src, const DiffractOptions& opt,
                            const JobRecord& job, const WorkShare& share, int nthreads) {
    const std::string& input_path = job.input_path;
    const int index = share.index, count = share.count;
    auto resolved = resolve_share(src, input_path, opt, index, count, nthreads);
    if (!resolved.ok()) return Result<bool>::failure(resolved);
    Share& j = resolved.value;
    if (opt.on_estimate) {  // the share's own job and terms
        JobEstimate e = detail::job_estimate(opt, j.f, nthreads);
        e.job = j.job;
        e.terms = j.terms;
        e.seconds = e.terms / e.rate;
        opt.on_estimate(e);
    }
    std::map<std::string, std::vector<float>> units;
    double done = 0;
    DiffractOptions run = opt;
    run.max_terms = INFINITY;  // bounded above, by the share's own terms
    run.on_estimate = {};
    run.progress = {};
    run.scene_sum_propagator = unit_propagator(j, opt.progress, units, done);
    OIIO::ImageBuf whole;
    if (auto r = DiffractPlan(run).diffract(whole, src, j.f, input_path, nthreads); !r.ok()) return r;
    std::vector<std::string> order;  // by name, as OpenEXR stores them
    for (const auto& unit : units) order.push_back(unit.first);
    const OIIO::ImageSpec spec = share_spec(whole.spec(), j, order, job, share);
    share_image.reset(spec);
    // each unit's rows written once, straight into its channel of the share file
    const OIIO::stride_t row = OIIO::stride_t(j.f.in.width) * sizeof(float);
    for (int c = 0; c < spec.nchannels; ++c)
        if (!share_image.set_pixels(OIIO::ROI(0, spec.width, spec.y, spec.y + spec.height, 0, 1, c, c + 1),
                             OIIO::TypeDesc::FLOAT, units[order[c]].data() + size_t(j.sh.row_begin) * j.f.in.width,
                             sizeof(float), row))
            return Result<bool>::failure(input_path + ": cannot fill the share image: " + share_image.geterror());
    share_image.specmod().attribute(record_name("checksum"), pixel_checksum(share_image));
    return Result<bool>::success(true);
}

Result<ShareFile> read_share(const std::string& path) {
    auto fail = [&path](const std::string& m) { return Result<ShareFile>::failure(path + ": " + m); };
    ShareFile p;
    p.path = path;
    auto image = read_image(path);
    if (!image.ok()) return Result<ShareFile>::failure(image.error);
    p.image = std::move(image.value);
    const OIIO::ImageSpec& spec = p.image.spec();
    bool* old = &p.old_spelling;
    const std::string share = share_record(spec, "", old);
    if (share.empty()) return fail("not a wavecam share file: no wavecam.share in its header");
    auto k = parse_share(share);
    int ub = 0, ue = 0, rb = 0, re = 0;
    p.wavelengths = int_record(spec, "wavelength-count", old);
    p.runs = int_record(spec, "runs", old);
    // propagations per wavelength: 1 for colour light, 3 (one per channel) for monochrome light
    const int per = int_record(spec, "propagations", old, 1);
    p.width = spec.full_width;
    p.height = spec.full_height;
    p.input = share_record(spec, "input", old);
    p.input_fingerprint = share_record(spec, "input-fingerprint", old);
    p.job = share_record(spec, "job", old);
    p.decision = share_record(spec, "decision", old);
    if (!k.ok() || !parse_range(share_record(spec, "units", old), ub, ue) ||
        !parse_range(share_record(spec, "rows", old), rb, re) || p.wavelengths < 1 || p.runs < 1 ||
        (per != 1 && per != 3) || p.input.empty() || p.input_fingerprint.empty() || p.job.empty())
        return fail("corrupt: its wavecam.share header is incomplete");
    auto layout = work_share(k.value.index, k.value.count, p.wavelengths, p.runs, p.height);
    if (!layout.ok() || layout.value.unit_begin != ub || layout.value.unit_end != ue ||
        layout.value.row_begin != rb || layout.value.row_end != re || spec.y != rb || spec.height != re - rb)
        return fail("corrupt: its header's units and rows are not share " + share + "'s");
    p.share = layout.value;
    const std::string sum = share_record(spec, "checksum", old);
    if (sum != pixel_checksum(p.image))
        return fail("corrupt: its pixels do not match the checksum in its header");
    // the settings under the spelling its share record has
    const std::string settings = (p.old_spelling ? kOldRecordPrefix : kRecordPrefix) + std::string(kSettingPrefix);
    for (const auto& a : spec.extra_attribs) {
        const std::string name = a.name().string();
        if (name.rfind(settings, 0) == 0) p.settings[name.substr(settings.size())] = a.get_string();
    }
    if (job_fingerprint(p.input_fingerprint, p.settings) != p.job)
        return fail("corrupt: its settings do not match the job fingerprint in its header");
    // unit u's propagations are spectral indices (u / runs) * per + c, c < per (spectrum.h)
    for (int u = ub; u < ue; ++u)
        for (int c = 0; c < per; ++c)
            if (const std::string name = channel_name(u / p.runs * per + c, u % p.runs, +1); spec.channelindex(name) < 0)
                return fail("corrupt: channel " + name + " is missing");
    return Result<ShareFile>::success(std::move(p));
}

Result<bool> check_share_set(const std::vector<ShareFile>& shares) {
    if (shares.empty()) return Result<bool>::failure("no share files given");
    std::vector<std::string> problems;
    const std::string input = majority<std::string>(shares, [](const ShareFile& p) { return p.input_fingerprint; });
    const SettingsText settings = majority<SettingsText>(shares, [](const ShareFile& p) { return p.settings; });
    const int count = majority<int>(shares, [](const ShareFile& p) { return p.share.count; });
    const std::string decision = majority<std::string>(shares, [](const ShareFile& p) { return p.decision; });
    std::map<int, const ShareFile*> seen;
    for (const auto& p : shares) {
        const size_t before = problems.size();
        if (p.input_fingerprint != input) {
            const ShareFile& other = *std::find_if(shares.begin(), shares.end(),
                                                   [&](const ShareFile& q) { return q.input_fingerprint == input; });
            problems.push_back(share_name(p) + ": made from another input (" + p.input + ", fingerprint " +
                               p.input_fingerprint + "; the other shares: " + other.input + ", fingerprint " + input +
                               ")");
        }
        std::set<std::string> keys;
        for (const auto& kv : p.settings) keys.insert(kv.first);
        for (const auto& kv : settings) keys.insert(kv.first);
        for (const auto& key : keys) {
            auto mine = p.settings.find(key), theirs = settings.find(key);
            const std::string a = mine == p.settings.end() ? "(default)" : "'" + mine->second + "'";
            const std::string b = theirs == settings.end() ? "(default)" : "'" + theirs->second + "'";
            if (a == b) continue;
            problems.push_back(share_name(p) + ": " + (key == "seed" ? "another seed" : "another setting") + ": " +
                               key + " " + a + " (the other shares: " + b + ")");
        }
        // shares that decided otherwise (on another device) would not add up to the job bit for bit
        if (!p.decision.empty() && !decision.empty() && p.decision != decision)
            problems.push_back(share_name(p) + ": decided otherwise: " + p.decision + " (the other shares: " +
                               decision + ")");
        if (p.share.count != count)
            problems.push_back(share_name(p) + ": from a split into " + std::to_string(p.share.count) +
                               " shares; the other shares are of " + std::to_string(count));
        if (problems.size() != before) continue;
        if (auto it = seen.find(p.share.index); it != seen.end())
            problems.push_back(share_name(p) + ": given twice (also " + it->second->path + ")");
        else
            seen[p.share.index] = &p;
    }
    std::string missing;
    for (int k = 1; k <= count; ++k)
        if (!seen.count(k)) missing += (missing.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(count);
    if (!missing.empty())
        problems.push_back("share" + std::string(missing.find(',') == std::string::npos ? " " : "s ") + missing +
                           " missing (given: " + std::to_string(seen.size()) + " of " + std::to_string(count) + ")");
    if (problems.empty()) return Result<bool>::success(true);
    std::string all;
    for (const auto& m : problems) all += (all.empty() ? "" : "\n") + m;
    return Result<bool>::failure(all);
}

MonochromePropagator stored_units(const std::vector<ShareFile>& shares) {
    // Every unit's rows gathered into one full-height image per channel name.
    auto units = std::make_shared<std::map<std::string, std::vector<float>>>();
    const int W = shares.front().width, H = shares.front().height, R = shares.front().runs;
    for (const auto& p : shares) {
        const OIIO::ImageSpec& spec = p.image.spec();
        const size_t rows = size_t(spec.height), C = size_t(spec.nchannels);
        std::vector<float> px(size_t(W) * rows * C);
        p.image.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());
        for (size_t c = 0; c < C; ++c) {
            auto& unit = (*units)[spec.channelnames[c]];
            if (unit.empty()) unit.assign(size_t(W) * H, 0.0f);
            float* dst = unit.data() + size_t(spec.y) * W;
            for (size_t q = 0; q < size_t(W) * rows; ++q) dst[q] = px[q * C + c];
        }
    }
    return [units, R](const MonochromeScene& mono, double, float* irradiance, const ProgressFn&) {
        const size_t n = size_t(mono.camera.width) * mono.camera.height;
        // The same sum, in the same order, as diffract_monochrome's runs.
        for (int r = 0; r < R; ++r) {
            const std::string name = channel_name(mono.spectral_index, r, mono.sign);
            auto it = units->find(name);
            if (it == units->end() || it->second.size() != n)
                return Result<bool>::failure("the shares hold no channel " + name + " (the input needs it)");
            for (size_t p = 0; p < n; ++p) irradiance[p] += it->second[p];
        }
        return Result<bool>::success(true);
    };
}

}  // namespace wavecam
