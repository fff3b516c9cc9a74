// Fuzzes description files: any bytes give a description or an error naming the file.
#include <cstdlib>
#include <string>

#include "front/description.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto r = wavecam::front::parse_description(text, "/tmp/fuzz/shot.wavecam");
    if (!r.ok() && r.error.rfind("/tmp/fuzz/shot.wavecam: ", 0) != 0) std::abort();
    return 0;
}
