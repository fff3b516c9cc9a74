#include "description.h"

#include <OpenImageIO/filesystem.h>

#include <algorithm>
#include <filesystem>
#include <toml++/toml.h>

namespace wavecam::front {
namespace {

// A TOML value as the text a person would type on the command line.
bool value_text(const toml::node& node, std::string& out) {
    if (auto s = node.value<std::string>()) out = *s;
    else if (auto i = node.value<int64_t>()) out = std::to_string(*i);
    else if (auto b = node.value<bool>()) out = *b ? "true" : "false";
    else if (auto d = node.value<double>()) out = std::to_string(*d);
    else if (const toml::array* a = node.as_array()) {
        out.clear();
        for (const toml::node& item : *a) {
            std::string t;
            if (!value_text(item, t)) return false;
            out += (out.empty() ? "" : ",") + t;
        }
    } else return false;
    return true;
}

// True if `inner` lies within `folder` (both made absolute and normal, symlinks resolved).
bool inside(const std::filesystem::path& folder, const std::filesystem::path& inner) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path a = fs::weakly_canonical(folder, ec), b = fs::weakly_canonical(inner, ec);
    return std::mismatch(a.begin(), a.end(), b.begin(), b.end()).first == a.end();
}

}  // namespace

Result<Description> read_description(const std::string& path) {
    std::string text;
    if (!OIIO::Filesystem::read_text_file(path, text)) return Result<Description>::failure(path + ": cannot be read");
    return parse_description(text, path);
}

Result<Description> parse_description(std::string_view text, const std::string& path) {
    namespace fs = std::filesystem;
    auto fail = [&path](const std::string& m) { return Result<Description>::failure(path + ": " + m); };
    toml::table doc;
    try {
        doc = toml::parse(text, path);
    } catch (const toml::parse_error& e) {
        const auto& where = e.source().begin;
        return fail("line " + std::to_string(where.line) + ": not a wavecam description (TOML): " +
                    std::string(e.description()));
    } catch (const std::exception& e) {
        return fail(std::string("cannot be read: ") + e.what());
    }
    Description d;
    for (const auto& [k, node] : doc) {
        const std::string key(k.str());
        std::string text;
        if (!value_text(node, text)) return fail(key + ": expected a string, number, true/false or a list");
        if (key == "source") d.source = text;
        else d.settings[key] = text;
    }
    if (d.source.empty()) return fail("source: missing; expected the path of the render to diffract");
    const fs::path folder = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
    const fs::path source = folder / d.source;
    if (fs::path(d.source).is_absolute() || !inside(folder, source))
        return fail("source: '" + d.source + "' escapes the description's folder; expected a path inside it");
    if (!OIIO::Filesystem::is_regular(source.string()))
        return fail("source: '" + d.source + "' does not exist (looked for " + source.string() + ")");
    d.source = source.string();
    // A mask image, like the source, is found beside this file and stays inside its folder.
    if (auto a = d.settings.find("aperture"); a != d.settings.end() && a->second.rfind("mask:", 0) == 0) {
        const std::string file = a->second.substr(5);
        if (fs::path(file).is_absolute() || !inside(folder, folder / file))
            return fail("aperture: mask '" + file + "' escapes the description's folder; expected a path inside it");
        a->second = "mask:" + (folder / file).string();
    }
    return Result<Description>::success(std::move(d));
}

}  // namespace wavecam::front
