#include "units.h"
#include <cmath>
#include <cstdlib>
#include <string>

namespace wavecam::trace {

namespace {
struct Unit {
    const char* name;
    double metres;
};
constexpr Unit kUnits[] = {{"nm", 1e-9}, {"um", 1e-6}, {"mm", 1e-3}, {"cm", 1e-2}, {"m", 1.0}};
}  // namespace

Result<double> parse_length(std::string_view text, std::string_view field) {
    const std::string s(text);
    const char* begin = s.c_str();
    char* end = nullptr;
    const double number = std::strtod(begin, &end);
    const std::string unit(end);
    const std::string where = std::string(field) + " '" + s + "'";
    if (end == begin || !std::isfinite(number))
        return Error{where + ": expected a number with a unit, e.g. 0.5mm"};
    if (unit.empty()) return Error{where + ": missing unit (nm, um, mm, cm or m)"};
    for (const Unit& u : kUnits) {
        if (unit == u.name) {
            if (number <= 0) return Error{where + ": must be positive"};
            return number * u.metres;
        }
    }
    return Error{where + ": unknown unit '" + unit + "' (nm, um, mm, cm or m)"};
}

}  // namespace wavecam::trace
