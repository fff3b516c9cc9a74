// Fuzzes the unit parser: any text must give a value or an error naming the field, never a
// crash, and a value must be what the text says (finite, or +inf only where allowed).
#include <cmath>
#include <cstdlib>
#include <string>

#include "wavecam/units.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    for (auto r : {wavecam::parse_length(text, "f"), wavecam::parse_angle(text, "f"),
                   wavecam::parse_length_or_inf(text, "f")}) {
        if (r.ok() && std::isnan(r.value)) std::abort();
        if (!r.ok() && r.error.rfind("f: ", 0) != 0) std::abort();
    }
    if (wavecam::parse_length(text, "f").ok() && std::isinf(wavecam::parse_length(text, "f").value)) std::abort();
    auto c = wavecam::parse_whole_number(text, "f", 1, 1000);
    if (c.ok() && (c.value < 1 || c.value > 1000)) std::abort();
    auto b = wavecam::parse_bytes(text, "f");
    if (b.ok() && !(b.value > 0 && std::isfinite(b.value))) std::abort();
    return 0;
}
