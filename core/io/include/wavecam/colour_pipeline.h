// Output colour through OpenColorIO: wavecam integrates spectra to CIE XYZ (D65) and lets the
// config turn XYZ into the output space. The config is the one wavecam ships unless another
// is named.
#pragma once
#include <OpenColorIO/OpenColorIO.h>
#include <string>
#include "wavecam/matrix3.h"
#include "wavecam/result.h"

namespace wavecam {

// The colour space every wavecam config must have: CIE 1931 XYZ with a D65 white.
constexpr const char* kXyzColorspace = "CIE-XYZ-D65";

class ColourConfig {
public:
    const std::string& path() const { return path_; }
    bool has_colorspace(const std::string& name) const;
    // The config's own name of a colour space given by name or alias ("" when it has none).
    std::string canonical_name(const std::string& name) const;
    // The linear map XYZ -> `space` (checked to be linear); fails for a non-linear space.
    Result<Matrix3> xyz_to_rgb_matrix(const std::string& space) const;
    // Converts `count` interleaved RGB triplets in place from XYZ to `space`.
    Result<bool> convert_from_xyz(float* rgb, size_t count, const std::string& space) const;
    // ... from `from` to `to`.
    Result<bool> convert(float* rgb, size_t count, const std::string& from, const std::string& to) const;
    // The film's XYZ to the output `space`; with `desaturate`, colours outside its gamut are
    // pulled into it at constant luminance (out_of_gamut.h). A space that is not linear (a display
    // encoding) is mapped in the linear `working_space` on the way. Returns how many were mapped.
    Result<size_t> output_colour(float* xyz, size_t count, const std::string& space,
                                 const std::string& working_space, bool desaturate) const;

    friend Result<ColourConfig> load_colour_config(const std::string& path);

private:
    std::string path_;
    OCIO_NAMESPACE::ConstConfigRcPtr config_;
};

// Loads `path`, or when empty the first of: $WAVECAM_OCIO_CONFIG, share/wavecam/ocio/wavecam.ocio
// of the prefix holding the running binary (the wavecam command or the plugin), the configured
// install prefix's, the source tree's ocio_configs/wavecam.ocio.
Result<ColourConfig> load_colour_config(const std::string& path);

}  // namespace wavecam
