// Uses both installed libraries: the design formula from core, the shipped OCIO config from io.
#include <cstdio>

#include "wavecam/colour_pipeline.h"
#include "wavecam/pinhole_design.h"

int main() {
    const double d = wavecam::rayleigh_optimal_diameter(50e-3, 550e-9);
    auto config = wavecam::load_colour_config(WAVECAM_OCIO_CONFIG);
    if (!config.ok()) {
        std::fprintf(stderr, "%s\n", config.error.c_str());
        return 1;
    }
    std::printf("optimal pinhole %.4f mm; config %s\n", d * 1e3, config.value.path().c_str());
    return 0;
}
