#include "wavecam/units.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>

namespace wavecam {
namespace {

struct Unit {
    const char* name;
    double scale;
};

// Splits "0.3mm" into 0.3 and "mm"; fails on anything but a finite number followed by a suffix.
bool split_number(std::string_view text, double& number, std::string_view& suffix) {
    std::string s(text);
    if (s.empty() || std::isspace(static_cast<unsigned char>(s[0]))) return false;
    const char* begin = s.c_str();
    char* end = nullptr;
    number = std::strtod(begin, &end);
    if (end == begin || !std::isfinite(number)) return false;
    suffix = text.substr(static_cast<size_t>(end - begin));
    return true;
}

template <class T>
Result<T> expected(std::string_view field, const std::string& what, std::string_view text) {
    return Result<T>::failure(std::string(field) + ": expected " + what + ", got '" + std::string(text) + "'");
}

template <size_t N>
Result<double> parse_with_units(std::string_view text, std::string_view field, const Unit (&units)[N],
                                const char* expected_text) {
    double number = 0;
    std::string_view suffix;
    if (split_number(text, number, suffix))
        for (const Unit& u : units)
            if (suffix == u.name) return Result<double>::success(number * u.scale);
    return expected<double>(field, expected_text, text);
}

constexpr Unit kLengthUnits[] = {{"nm", 1e-9}, {"um", 1e-6}, {"\xC2\xB5m", 1e-6},
                                 {"mm", 1e-3}, {"cm", 1e-2}, {"m", 1.0}};
constexpr Unit kAngleUnits[] = {{"deg", M_PI / 180.0}, {"rad", 1.0}};
constexpr Unit kByteUnits[] = {{"GiB", 1073741824.0}, {"MiB", 1048576.0}, {"KiB", 1024.0},
                               {"GB", 1e9},           {"MB", 1e6},        {"KB", 1e3}};

}  // namespace

Result<double> parse_length(std::string_view text, std::string_view field) {
    return parse_with_units(text, field, kLengthUnits, "a length with a unit (nm, um, mm, cm, m), e.g. 0.3mm");
}

Result<double> parse_length_or_inf(std::string_view text, std::string_view field) {
    if (text == "inf" || text == "infinity")
        return Result<double>::success(std::numeric_limits<double>::infinity());
    return parse_with_units(text, field, kLengthUnits,
                            "a length with a unit (nm, um, mm, cm, m) or 'inf', e.g. 2m");
}

Result<double> parse_angle(std::string_view text, std::string_view field) {
    return parse_with_units(text, field, kAngleUnits, "an angle with a unit (deg, rad), e.g. 50deg");
}

Result<double> parse_bytes(std::string_view text, std::string_view field) {
    const char* what = "a size > 0 with a unit (KiB, MiB, GiB, KB, MB, GB), e.g. 16GiB";
    auto size = parse_with_units(text, field, kByteUnits, what);
    return size.ok() && !(size.value > 0) ? expected<double>(field, what, text) : size;
}

Result<long> parse_whole_number(std::string_view text, std::string_view field, long lo, long hi) {
    const std::string s(text);
    char* end = nullptr;
    const long v = s.empty() ? 0 : std::strtol(s.c_str(), &end, 10);
    if (s.empty() || *end != '\0' || v < lo || v > hi)
        return expected<long>(field, "a whole number from " + std::to_string(lo) + " to " + std::to_string(hi), text);
    return Result<long>::success(v);
}

std::string with_unit(double value, double scale, std::string_view unit) {
    std::ostringstream s;
    s << value / scale << unit;
    return s.str();
}

}  // namespace wavecam
