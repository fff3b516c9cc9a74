// The exact wave propagator (src/optics/propagation.cpp): the seed paper's two sums, scene ->
// pinhole samples -> film. Both are one vectorised phasor sum (src/optics/phasor_sum.h) and take
// path lengths as differences from a reference path in a cancellation-free form (docs/physics.md),
// so single-precision arithmetic keeps phases right for paths of 10^6 wavelengths and more.
#pragma once
#include <complex>
#include <vector>
#include "wavecam/aperture.h"
#include "wavecam/progress.h"
#include "wavecam/source.h"

namespace wavecam {

// The field arriving at each pinhole sample, premultiplied by the sample's area and 1/lambda,
// ready to be re-emitted: w_j = U(xi_j) dA_j / lambda. Structure of arrays.
struct PinholeField {
    std::vector<float> re, im;
};

// Coherent sum of all sources at every pinhole sample:
// U(xi) = sum_s a_s exp(i(phase_s + k (r_s - |P_s|))) / r_s  (finite sources; the common
// exp(i k |P_s|) is a per-source constant phase, irrelevant to irradiance and absorbed into
// phase_s), plane waves a_s exp(i(phase_s - k u_s . xi)).
// Returns false if cancelled through `progress`.
bool illuminate_pinhole(const ApertureSamples& samples, const std::vector<PointSource>& sources,
                        double wavelength, PinholeField& field, int nthreads = 0,
                        const ProgressFn& progress = {});

// Film points on the plane z = -film_distance.
struct FilmPoints {
    std::vector<float> x, y;
    double film_distance = 0.0;
    size_t size() const { return x.size(); }
};

// The pinhole's field `field` on its `samples`, re-emitted onto the `film` points at `wavelength`.
struct FilmPropagation {
    const ApertureSamples& samples;
    const PinholeField& field;
    const FilmPoints& film;
    double wavelength;
};

// Rayleigh-Sommerfeld I re-emission (Goodman, Introduction to Fourier Optics, eq. 3-41):
// U(x) = 1/(i lambda) sum_j U(xi_j) exp(i k r_j) / r_j * cos(theta_j) dA_j, cos(theta_j) = f / r_j,
// and adds scale * |U(x)|^2 to irradiance[t] for every film point t.
// Returns false if cancelled through `progress`.
bool accumulate_film_irradiance(const FilmPropagation& propagation, double scale, float* irradiance,
                                int nthreads = 0, const ProgressFn& progress = {});

// The film field U(x) of the sum above (before |U|^2), added to film_field[t].
bool add_film_field(const FilmPropagation& propagation, std::complex<double>* film_field, int nthreads = 0,
                    const ProgressFn& progress = {});

}  // namespace wavecam
