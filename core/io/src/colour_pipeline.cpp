#include "wavecam/colour_pipeline.h"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "wavecam/out_of_gamut.h"
#include "wavecam/threads.h"

namespace OCIO = OCIO_NAMESPACE;

namespace wavecam {
namespace {

// The installed config relative to the binary holding this code (the wavecam command in bin/,
// or the plugin in lib/[arch/]wavecam/), so a relocated install or .deb finds its own.
std::string config_beside_this_binary() {
    Dl_info info;
    if (!dladdr(reinterpret_cast<void*>(&config_beside_this_binary), &info) || !info.dli_fname) return {};
    std::error_code ec;
    std::filesystem::path dir = std::filesystem::canonical(info.dli_fname, ec).parent_path();
    for (int up = 0; up < 3 && !dir.empty(); ++up) {
        dir = dir.parent_path();
        const auto candidate = dir / "share" / "wavecam" / "ocio" / "wavecam.ocio";
        if (std::filesystem::is_regular_file(candidate, ec)) return candidate.string();
    }
    return {};
}

std::string default_config_path() {
    if (const char* env = std::getenv("WAVECAM_OCIO_CONFIG"); env && *env) return env;
    if (std::string beside = config_beside_this_binary(); !beside.empty()) return beside;
    std::error_code ec;
    for (const char* candidate : {WAVECAM_INSTALLED_OCIO_CONFIG, WAVECAM_SOURCE_OCIO_CONFIG})
        if (std::filesystem::is_regular_file(candidate, ec)) return candidate;
    return WAVECAM_INSTALLED_OCIO_CONFIG;
}

}  // namespace

Result<ColourConfig> load_colour_config(const std::string& path) {
    ColourConfig c;
    c.path_ = path.empty() ? default_config_path() : path;
    try {
        c.config_ = OCIO::Config::CreateFromFile(c.path_.c_str());
    } catch (const std::exception& e) {
        return Result<ColourConfig>::failure(c.path_ + ": not a usable OpenColorIO config: " + e.what());
    }
    if (!c.has_colorspace(kXyzColorspace))
        return Result<ColourConfig>::failure(c.path_ + ": colour space '" + kXyzColorspace +
                                             "' not found; wavecam needs it to turn spectra into colour");
    return Result<ColourConfig>::success(std::move(c));
}

bool ColourConfig::has_colorspace(const std::string& name) const {
    return config_ && config_->getColorSpace(name.c_str()) != nullptr;
}

std::string ColourConfig::canonical_name(const std::string& name) const {
    const auto space = config_ ? config_->getColorSpace(name.c_str()) : nullptr;
    return space ? space->getName() : std::string();
}

Result<bool> ColourConfig::convert_from_xyz(float* rgb, size_t count, const std::string& space) const {
    return convert(rgb, count, kXyzColorspace, space);
}

Result<bool> ColourConfig::convert(float* rgb, size_t count, const std::string& from, const std::string& to) const {
    for (const std::string& space : {from, to})
        if (!has_colorspace(space)) return Result<bool>::failure(path_ + ": colour space '" + space + "' not found");
    OCIO::ConstCPUProcessorRcPtr processor;
    try {
        processor = config_->getProcessor(from.c_str(), to.c_str())->getDefaultCPUProcessor();
    } catch (const std::exception& e) {
        return Result<bool>::failure(path_ + ": cannot convert '" + from + "' to '" + to + "': " + e.what());
    }
    // in runs of pixels: OCIO's scratch is one run (a whole frame's was 32 MiB a call, freshly
    // faulted in), and the runs spread over the threads (a CPU processor's apply is thread-safe)
    constexpr long kRun = 4096;
    const long runs = (long(count) + kRun - 1) / kRun;
    std::string failed;
    std::mutex failure;
    parallel_for(0, runs, 0, [&](int64_t r) {
        try {
            OCIO::PackedImageDesc desc(rgb + 3 * r * kRun, std::min<long>(kRun, long(count) - r * kRun), 1, 3);
            processor->apply(desc);
        } catch (const std::exception& e) {
            std::lock_guard<std::mutex> lock(failure);
            failed = e.what();
        }
    });
    if (!failed.empty())
        return Result<bool>::failure(path_ + ": cannot convert '" + from + "' to '" + to + "': " + failed);
    return Result<bool>::success(true);
}

Result<size_t> ColourConfig::output_colour(float* xyz, size_t count, const std::string& space,
                                           const std::string& working_space, bool desaturate) const {
    auto fail = [](const std::string& m) { return Result<size_t>::failure(m); };
    if (!desaturate) {
        if (auto r = convert_from_xyz(xyz, count, space); !r.ok()) return fail(r.error);
        return Result<size_t>::success(0);
    }
    // map in the output space itself when it is linear, else in the working space
    auto m = xyz_to_rgb_matrix(space);
    const std::string& linear = m.ok() ? space : working_space;
    if (!m.ok()) m = xyz_to_rgb_matrix(working_space);
    if (!m.ok()) return fail(m.error);
    if (!(std::fabs(determinant(m.value)) > 0))
        return fail(path_ + ": colour space '" + linear + "' has a singular XYZ matrix");
    const Vector3 primary_luminance = inverse(m.value)[1];  // row Y of RGB -> XYZ
    if (auto r = convert_from_xyz(xyz, count, linear); !r.ok()) return fail(r.error);
    const size_t mapped = desaturate_into_gamut(xyz, count, primary_luminance);
    if (linear != space)
        if (auto r = convert(xyz, count, linear, space); !r.ok()) return fail(r.error);
    return Result<size_t>::success(mapped);
}

Result<Matrix3> ColourConfig::xyz_to_rgb_matrix(const std::string& space) const {
    // Columns from the unit vectors; linearity checked on a scaled mixture.
    float probe[5][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.25f, 0.5f, 0.125f}, {2.5f, 5.0f, 1.25f}};
    if (auto r = convert_from_xyz(&probe[0][0], 5, space); !r.ok()) return Result<Matrix3>::failure(r.error);
    Matrix3 m;
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) m[row][col] = probe[col][row];
    for (int k = 0; k < 3; ++k) {
        const double expect_small = m[k][0] * 0.25 + m[k][1] * 0.5 + m[k][2] * 0.125;
        if (std::fabs(probe[3][k] - expect_small) > 1e-4 * (1 + std::fabs(expect_small)) ||
            std::fabs(probe[4][k] - 10 * probe[3][k]) > 1e-4 * (1 + std::fabs(probe[4][k])))
            return Result<Matrix3>::failure(path_ + ": colour space '" + space +
                                            "' is not linear; expected a scene-linear space for the radiance");
    }
    return Result<Matrix3>::success(m);
}

}  // namespace wavecam
