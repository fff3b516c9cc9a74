// The ImageBuf entry point: a render (RGB radiance + depth) in, the image a real pinhole camera
// of the given size makes out. ImageBufAlgo style: dst, src, options, nthreads; errors carried
// in dst (dst.geterror()), never thrown.
#pragma once
#include <OpenImageIO/imagebuf.h>
#include <string>
#include <vector>
#include "wavecam/render_input.h"
#include "wavecam/fast_diffraction.h"
#include "wavecam/scene_diffraction.h"

namespace wavecam {

// fast: PSF-grid convolution (the default); exact: the seed paper's random-phase sum over
// pinhole samples; incoherent: the exact sum with every source alone (small images).
enum class DiffractMethod { Fast, Exact, Incoherent };

struct DiffractOptions {
    DiffractMethod method = DiffractMethod::Fast;
    RenderReadOptions read;                        // depth channel, --fov
    DepthMeaning depth_meaning = DepthMeaning::Planar;
    double film_distance = 50e-3;                  // f, metres
    double pinhole = 0;                            // diameter (m); 0 = Rayleigh's optimum for f at 550 nm
    Aperture aperture;                             // shape (--aperture); its diameter comes from `pinhole`
    DiffractionSettings diffraction;               // exact methods: runs, seed, jitter, film subsamples
    FastSettings fast;                             // fast method: tiles, kernel size
    std::vector<double> wavelengths;               // explicit list (m); empty = wavelength_count in 400-700 nm
    int wavelength_count = 8;
    bool monochrome = false;                       // every channel through the same light (also when < 3 wavelengths)
    bool vignetting = true;                        // keep the natural cos^4 fall-off
    std::string colorconfig;                       // OCIO config; "" = the one wavecam ships
    std::string input_colorspace;                  // "" = the file's oiio:ColorSpace, else lin_rec709
    std::string output_colorspace;                 // "" = the input's
    double max_terms = 4e12;                       // refuse larger jobs (about an hour here)
    double max_memory = 16.0 * (1ull << 30);       // bytes; refuse jobs estimated to need more
    ProgressFn progress;
};

// The pinhole diameter the options resolve to (the optimum when none is given).
double resolved_pinhole(const DiffractOptions& opt);
// The aperture with that diameter.
Aperture resolved_aperture(const DiffractOptions& opt);

// Terms the job costs for an image of this size and field of view (for refusing and reporting).
double estimate_terms(const DiffractOptions& opt, const PinholeCamera& camera, const std::vector<float>& depth,
                      DepthMeaning meaning);

// Bytes the job needs at its peak (images, pinhole samples or PSF kernels), an upper estimate.
double estimate_memory(const DiffractOptions& opt, const PinholeCamera& camera);

// Diffracts `src`; `name` is used in error messages (the file name). dst gets float R, G, B in
// the output colour space, the source's depth channel, and every parameter in its header.
bool diffract(OIIO::ImageBuf& dst, const OIIO::ImageBuf& src, const std::string& name, const DiffractOptions& opt,
              int nthreads = 0);

}  // namespace wavecam
