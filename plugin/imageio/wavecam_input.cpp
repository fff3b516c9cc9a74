// wavecam.imageio.so: an OpenImageIO input plugin, so oiiotool and any OIIO application can
// run wavecam as a post-process step. A thin front: all physics is in core.
//
//   shot.exr.wavecam         (no such file needed) shot.exr diffracted; settings from
//                            `--iconfig wavecam:KEY VALUE` hints over the source's own
//                            `wavecam.KEY` metadata over defaults (front/settings.h's order)
//   shot.exr.wavecam?runs=8  settings in the name, too (name_query.h)
//   shot.wavecam             a description file (front/description.h)
//
// No exception leaves this file; errors go through OIIO's error reporting (and, for the one
// host that drops them, to stderr as well: see report_where_the_host_drops_it).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <set>

#include "../front/description.h"
#include "../front/estimate_line.h"
#include "name_query.h"
#include "result_cache.h"
#include "source_identity.h"
#include "wavecam/diffract_image.h"
#include "wavecam/units.h"

OIIO_PLUGIN_NAMESPACE_BEGIN

namespace {

constexpr const char* kExtension = ".wavecam";

using wavecam::front::Settings;

// oiiotool (2.4.7 and 3.x, oiiotool.cpp's input_file) opens an input through its ImageCache
// and, when that fails and no --iconfig was given, reports only `File does not exist` for a
// name that is not on disk (it checks Filesystem::exists, then asks the reader for its error
// only if the name exists). shot.exr.wavecam and ?key=value names are never on disk, so in
// that one case the plugin's message would be lost: write it to stderr too, once per message.
// Every other host (Python, iinfo, idiff, iconvert, ImageBuf, ImageInput::open) and oiiotool
// with --iconfig report the message themselves and get nothing on stderr from us.
void report_where_the_host_drops_it(const std::string& name, const ImageSpec& config, const std::string& message) {
#ifdef __GLIBC__
    const bool host_is_oiiotool = std::string(program_invocation_short_name) == "oiiotool";
#else
    const bool host_is_oiiotool = false;
#endif
    if (!host_is_oiiotool || Filesystem::is_regular(name)) return;
    for (const ParamValue& p : config.extra_attribs)
        if (p.name() != "oiio:UnassociatedAlpha") return;  // --iconfig given: oiiotool reports it
    static std::mutex printed_mutex;
    static std::set<std::string> printed;  // oiiotool may open a failing name twice
    std::lock_guard<std::mutex> lock(printed_mutex);
    if (printed.insert(message).second) std::fprintf(stderr, "wavecam ERROR: %s\n", message.c_str());
}

// Computed images, by source file (its identity and version) and settings: oiiotool opens one
// input several times per command. The last 4, at most 512 MiB of pixels (docs/oiio.md).
wavecam::plugin::ResultCache g_results(4, size_t(512) << 20);
// Plans by settings: frames of a sequence (oiiotool --frames) share one kernel table. A handful
// is kept; a host that cycles through more settings rebuilds.
std::mutex g_plans_mutex;
std::map<std::string, std::shared_ptr<wavecam::DiffractPlan>> g_plans;
constexpr size_t kMaxPlans = 4;
// Names being opened on this thread: the source must not re-enter the plugin for itself.
thread_local std::set<std::string> t_opening;

}  // namespace

class WavecamInput final : public ImageInput {
public:
    const char* format_name() const override { return "wavecam"; }
    int supports(string_view feature) const override { return feature == "arbitrary_metadata"; }

    // A plain filesystem check: OIIO calls this holding its plugin mutex, so it must not
    // open anything through OIIO (that would deadlock).
    bool valid_file(const std::string& filename) const override {
        try {
            const std::string path = filename.substr(0, filename.find('?'));
            if (!Strutil::ends_with(path, kExtension)) return false;
            return Filesystem::is_regular(path) ||
                   Filesystem::is_regular(path.substr(0, path.size() - std::strlen(kExtension)));
        } catch (...) {  // no exception leaves the plugin
            return false;
        }
    }

    bool open(const std::string& name, ImageSpec& newspec) override { return open(name, newspec, ImageSpec()); }

    bool open(const std::string& name, ImageSpec& newspec, const ImageSpec& config) override {
        try {
            if (open_checked(name, newspec, config)) return true;
        } catch (const std::bad_alloc&) {
            errorfmt("{}: out of memory (a job larger than this machine; lower the image size, wavecam:wavelengths "
                     "or wavecam:runs, or wavecam:max-memory so that such jobs are refused before the work)",
                     name);
        } catch (const std::exception& e) {
            errorfmt("{}: {}", name, e.what());
        } catch (...) {
            errorfmt("{}: unexpected failure", name);
        }
        const std::string message = geterror(false);
        report_where_the_host_drops_it(name, config, message);
        return false;
    }

    bool close() override {
        m_image.reset();
        return true;
    }

    bool read_native_scanline(int subimage, int miplevel, int y, int /*z*/, void* data) override {
        try {
            if (!m_image || subimage != 0 || miplevel != 0 || y < m_spec.y || y >= m_spec.y + m_spec.height)
                return false;
            const ROI row(m_spec.x, m_spec.x + m_spec.width, y, y + 1, 0, 1, 0, m_spec.nchannels);
            return m_image->get_pixels(row, m_spec.format, data);
        } catch (const std::exception& e) {
            errorfmt("wavecam: {}", e.what());
            return false;
        }
    }

private:
    std::shared_ptr<const ImageBuf> m_image;

    bool open_checked(const std::string& name, ImageSpec& newspec, const ImageSpec& config) {
        namespace front = wavecam::front;
        auto split = wavecam::plugin::split_query(name);
        if (!split.ok()) return fail(split.error);
        const std::string& path = split.value.path;
        const Settings& query = split.value.settings;
        front::SettingSources sources;
        sources.given = query;  // ?KEY=VALUE wins over --iconfig wavecam:KEY VALUE
        for (const ParamValue& p : config.extra_attribs) {
            const std::string n = p.name().string();
            if (n.rfind("wavecam:", 0) == 0) {
                sources.given.emplace(n.substr(8), p.get_string());
            } else if (Strutil::istarts_with(n, "wavecam") && n.size() > 7) {
                // wavecam.pinhole, wavecam_pinhole, Wavecam:pinhole: a hint meant for wavecam, misspelt,
                // never ignored (it would leave the default in force)
                const std::string key = n.substr(8);
                const std::string nearest = wavecam::front::nearest_key(key);
                return fail("--iconfig " + n + ": not a wavecam hint; expected wavecam:KEY (a colon, lower case)" +
                            (nearest.empty() ? "" : ", e.g. --iconfig wavecam:" + nearest + " " + p.get_string()));
            }
        }
        sources.given_name = [query](const std::string& key) {
            return query.count(key) ? "?" + key + "= in the name" : "--iconfig wavecam:" + key;
        };
        std::string source;
        if (Filesystem::is_regular(path)) {  // a description file
            auto d = front::read_description(path);
            if (!d.ok()) return fail(d.error);
            source = d.value.source;
            sources.description = d.value.settings;
            sources.description_path = path;
        } else {
            source = path.substr(0, path.size() - std::strlen(kExtension));
        }

        // OIIO's words for a missing file name its ImageCache ("Invalid image file"); say it
        // plainly. A source that is itself a wavecam name need not exist on disk.
        if (!Filesystem::exists(source) && !Strutil::ends_with(source.substr(0, source.find('?')), kExtension))
            return fail(source + ": no such file, expected the render to diffract");

        const std::string key = result_key(source, sources);
        if (auto kept = g_results.find(key)) return publish(kept, newspec);
        if (t_opening.count(source)) return fail(source + ": refers to itself through the wavecam plugin");
        t_opening.insert(source);
        auto image = compute(source, sources);
        t_opening.erase(source);
        if (!image.ok()) return fail(image.error);
        g_results.insert(key, image.value);
        return publish(image.value, newspec);
    }

    // What a result is kept under: the source file (which file, which version of it) as named,
    // a mask aperture's file the same way, and every setting given or described.
    // Each part is written with its length first: a decoded value may hold any byte.
    static std::string result_key(const std::string& source, const wavecam::front::SettingSources& sources) {
        std::string key;
        auto add = [&key](const std::string& part) { key += std::to_string(part.size()) + ":" + part; };
        add(wavecam::plugin::source_identity(source));
        add(source);
        for (const Settings* layer : {&sources.given, &sources.description}) {
            add(layer == &sources.given ? "given" : "described");
            for (const auto& [k, v] : *layer) {
                add(k);
                add(v);
                if (k == "aperture" && v.rfind("mask:", 0) == 0) add(wavecam::plugin::source_identity(v.substr(5)));
            }
        }
        return key;
    }

    using Computed = wavecam::Result<std::shared_ptr<const ImageBuf>>;
    Computed compute(const std::string& source, const wavecam::front::SettingSources& sources) {
        double max_bytes = wavecam::DiffractOptions{}.max_memory;  // the limit given, before the source is read
        if (auto limit = sources.given.find("max-memory"); limit != sources.given.end())
            if (auto b = wavecam::parse_bytes(limit->second, "max-memory"); b.ok()) max_bytes = b.value;
        std::string part;  // the part (subimage) named by the user or the description file
        for (const Settings* layer : {&sources.description, &sources.given})
            if (auto named = layer->find("subimage"); named != layer->end()) part = named->second;
        auto read = wavecam::read_render(source, part, max_bytes);
        if (!read.ok())  // (a part to name: how to name it)
            return Computed::failure(read.field == "subimage"
                                         ? wavecam::front::word_failure(wavecam::Result<bool>::failure(read),
                                                                        wavecam::front::Front::Plugin)
                                         : read.error);
        const ImageBuf& src = read.value;
        auto settings = wavecam::front::resolve_settings(src.spec(), sources);
        if (!settings.ok()) return Computed::failure(source + ": " + settings.error);
        wavecam::front::show_notes(settings.value.notes);
        // the scene-sum methods' estimate before their work, in the command's words
        settings.value.options.on_estimate = [](const wavecam::JobEstimate& e) {
            wavecam::front::show_notes({"estimate: " + wavecam::front::estimate_line(e)});
        };
        std::string plan_key;
        for (const auto& [k, v] : settings.value.text) plan_key += k + "=" + v + "\n";
        plan_key += settings.value.options.read.fov_from;
        std::shared_ptr<wavecam::DiffractPlan> plan;
        {
            std::lock_guard<std::mutex> lock(g_plans_mutex);
            if (g_plans.size() >= kMaxPlans && !g_plans.count(plan_key)) g_plans.clear();
            auto& slot = g_plans[plan_key];
            if (!slot) slot = std::make_shared<wavecam::DiffractPlan>(settings.value.options);
            plan = slot;
        }
        auto dst = std::make_shared<ImageBuf>();
        if (auto r = plan->diffract(*dst, src, source); !r.ok())
            return Computed::failure(wavecam::front::word_failure(r, wavecam::front::Front::Plugin));
        if (const std::string edge = dst->spec().get_string_attribute("wavecam.edge"); !edge.empty())
            wavecam::front::show_notes({source + ": " + edge});
        return Computed::success(dst);
    }

    bool publish(const std::shared_ptr<const ImageBuf>& image, ImageSpec& newspec) {
        m_image = image;
        m_spec = image->spec();
        newspec = m_spec;
        return true;
    }

    bool fail(const std::string& message) {
        errorfmt("{}", message);
        return false;
    }
};

OIIO_PLUGIN_EXPORTS_BEGIN

OIIO_EXPORT int wavecam_imageio_version = OIIO_PLUGIN_VERSION;
OIIO_EXPORT const char* wavecam_imageio_library_version() { return "wavecam 0.1"; }
OIIO_EXPORT ImageInput* wavecam_input_imageio_create() {
    try {
        return new WavecamInput;
    } catch (...) {  // no exception leaves the plugin
        return nullptr;
    }
}
OIIO_EXPORT const char* wavecam_input_extensions[] = {"wavecam", nullptr};

OIIO_PLUGIN_EXPORTS_END

OIIO_PLUGIN_NAMESPACE_END
