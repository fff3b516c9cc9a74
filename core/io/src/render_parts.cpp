#include "render_parts.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include <memory>
#include <vector>

namespace wavecam::detail {
namespace {

struct Part {
    std::string name;
    std::vector<std::string> channels;
};

// Every part's name and channels, from the headers alone (no pixels are read).
std::vector<Part> list_parts(const std::string& path) {
    std::vector<Part> parts;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        OIIO::geterror();  // (the reader reports the failure itself)
        return parts;
    }
    for (int s = 0; in->seek_subimage(s, 0); ++s) {
        const OIIO::ImageSpec& spec = in->spec();
        std::string name = spec.get_string_attribute("oiio:subimagename");
        if (name.empty()) name = "#" + std::to_string(s);  // (a format that names no parts)
        parts.push_back({name, spec.channelnames});
    }
    in->close();
    return parts;
}

std::string describe(const std::vector<Part>& parts) {
    std::string text;
    for (const Part& p : parts)
        text += (text.empty() ? "" : ", ") + ("\"" + p.name + "\" (" + OIIO::Strutil::join(p.channels, ", ") + ")");
    return text;
}

bool has(const Part& p, const std::string& channel) {
    for (const std::string& c : p.channels)
        if (c == channel || OIIO::Strutil::ends_with(c, "." + channel)) return true;
    return false;
}

// Where no part holds R, G, B and Z together but one holds R, G, B and another Z: choosing one
// cannot help, joining them does.
std::string split_note(const std::string& path, const std::vector<Part>& parts) {
    const Part *rgb = nullptr, *depth = nullptr;
    for (const Part& p : parts) {
        const bool colour = has(p, "R") && has(p, "G") && has(p, "B");
        if (colour && has(p, "Z")) return {};
        if (colour && !rgb) rgb = &p;
        if (has(p, "Z") && !depth) depth = &p;
    }
    if (!rgb || !depth) return {};
    return " (no part here holds both: R, G, B are in \"" + rgb->name + "\", Z in \"" + depth->name +
           "\"; join them into one first, e.g. oiiotool " + path + " --subimage " + rgb->name + " " + path +
           " --subimage " + depth->name + " --chappend -o joined.exr)";
}

}  // namespace

Result<int> choose_part(const std::string& path, const std::string& name) {
    const std::vector<Part> parts = list_parts(path);
    if (parts.empty() || (parts.size() == 1 && name.empty())) return Result<int>::success(0);  // (or unreadable)
    for (size_t s = 0; s < parts.size() && !name.empty(); ++s)
        if (parts[s].name == name) return Result<int>::success(int(s));
    // no name: the one part that holds a render (R, G, B and Z), the others passing through
    std::vector<int> renders;
    for (size_t s = 0; s < parts.size() && name.empty(); ++s)
        if (has(parts[s], "R") && has(parts[s], "G") && has(parts[s], "B") && has(parts[s], "Z")) renders.push_back(int(s));
    if (renders.size() == 1) return Result<int>::success(renders.front());
    const std::string m = path + ": " + std::to_string(parts.size()) + " part" + (parts.size() == 1 ? "" : "s") +
                          " (subimages): " + describe(parts) + "; ";
    if (name.empty())
        return Result<int>::failure(m + "wavecam diffracts one part, which holds R, G, B and the depth channel "
                                        "(the others pass through)" +
                                        split_note(path, parts),
                                    ErrorKind::Missing, "subimage");
    return Result<int>::failure(m + "none is named \"" + name + "\", expected one of these names", ErrorKind::Invalid,
                                "subimage");
}

std::string other_part_note(const OIIO::ImageBuf& image, const std::string& channel) {
    if (image.nsubimages() <= 1) return {};
    const std::string path = image.name();
    const std::vector<Part> parts = list_parts(path);
    const std::string chosen = image.spec().get_string_attribute("oiio:subimagename");
    for (const Part& p : parts) {
        if (p.name == chosen) continue;
        for (const std::string& c : p.channels)
            if (c == channel || OIIO::Strutil::ends_with(c, "." + channel))
                return "; channel '" + c + "' is in part \"" + p.name + "\" of this file, and wavecam reads one part "
                       "(\"" + chosen + "\"): join the two into one first, e.g. oiiotool " + path + " --subimage " +
                       chosen + " " + path + " --subimage " + p.name +
                       " --chappend -o joined.exr";
    }
    return {};
}

}  // namespace wavecam::detail
