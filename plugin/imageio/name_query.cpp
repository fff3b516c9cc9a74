#include "name_query.h"

#include <OpenImageIO/strutil.h>

#include <cctype>

namespace wavecam::plugin {
namespace {

constexpr const char* kExpected = "expected KEY=VALUE items joined by &, e.g. ?pinhole=0.2mm&runs=8";

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    c = char(std::tolower(static_cast<unsigned char>(c)));
    return c >= 'a' && c <= 'f' ? c - 'a' + 10 : -1;
}

// "%20" -> " ", byte by byte; the first '%' that is not followed by two hex digits, as text,
// in `bad` (the result is then unused).
std::string percent_decoded(const std::string& text, std::string& bad) {
    std::string out;
    for (size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '%') {
            out += text[i];
            continue;
        }
        const int hi = i + 1 < text.size() ? hex_digit(text[i + 1]) : -1;
        const int lo = i + 2 < text.size() ? hex_digit(text[i + 2]) : -1;
        if (hi < 0 || lo < 0) {
            bad = text.substr(i, 3);
            return {};
        }
        out += char(hi * 16 + lo);
        i += 2;
    }
    return out;
}

}  // namespace

Result<NameQuery> split_query(const std::string& name) {
    using R = Result<NameQuery>;
    const size_t q = name.find('?');
    NameQuery r{name.substr(0, q), {}};
    if (q == std::string::npos) return R::success(std::move(r));
    for (const auto& piece : OIIO::Strutil::splits(name.substr(q + 1), "&")) {
        const std::string item(piece);
        const size_t eq = item.find('=');
        if (item.empty())
            return R::failure(name + ": an empty item after '?' or '&' (a trailing or doubled '&'); " + kExpected);
        if (eq == std::string::npos)
            return R::failure(name + ": '" + item + "' has no '=' and value; " + kExpected);
        std::string bad;
        const std::string key = percent_decoded(item.substr(0, eq), bad);
        const std::string value = bad.empty() ? percent_decoded(item.substr(eq + 1), bad) : std::string();
        if (!bad.empty())
            return R::failure(name + ": '" + bad + "' in '" + item +
                              "' is not a percent escape; expected % and two hex digits, e.g. %20 for a space, %25 "
                              "for %");
        if (key.empty()) return R::failure(name + ": '" + item + "' has no setting name; " + kExpected);
        if (!r.settings.emplace(key, value).second)
            return R::failure(name + ": ?" + key + "= given twice; give each setting once");
    }
    return R::success(std::move(r));
}

}  // namespace wavecam::plugin
