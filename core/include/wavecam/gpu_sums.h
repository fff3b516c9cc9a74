// The exact propagator's two direct sums (propagation.h) on a GPU through Vulkan compute
// (src/gpu, docs/gpu.md): the same terms, the same float phases in turns with exact reduction,
// float blocks of 1024 terms added in double (or as a compensated float pair on devices without
// double precision). Any Vulkan device runs it, Mesa's lavapipe on the CPU included.
//
// Made on a device handle's Vulkan context (compute_device.h: the handle makes one for itself,
// and builds its pipelines once), then called as often as needed; calls on one GpuSums are
// serialised. Errors are values, never exceptions.
#pragma once
#include <complex>
#include <memory>
#include <string>
#include <vector>

#include "wavecam/aperture.h"
#include "wavecam/compute_device.h"
#include "wavecam/progress.h"
#include "wavecam/propagation.h"
#include "wavecam/result.h"
#include "wavecam/source.h"

namespace wavecam {

// Several runs' weights on one set of sources: weights[r * sources.size() + s] replaces source
// s's amplitude exp(i phase) in run r, for r < runs.
struct RunWeights {
    const std::vector<std::complex<double>>& weights;
    int runs;
};

class GpuSums {
public:
    // The sums' pipelines on `device`'s Vulkan context; fails on a handle without one, naming
    // why (its error(): the Vulkan driver, a device, a compute queue missing). double_blocks
    // false: the compensated float pair even where the device has double precision.
    static Result<std::shared_ptr<GpuSums>> create(const ComputeDevice& device, bool double_blocks = true);

    ~GpuSums();
    GpuSums(const GpuSums&) = delete;
    GpuSums& operator=(const GpuSums&) = delete;

    const std::string& device_name() const;  // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    const std::string& driver() const;       // driver name and version, e.g. "llvmpipe, Mesa 22.3.6 (LLVM 15.0.6)"
    bool double_blocks() const;              // blocks added in double (else compensated float)
    std::string description() const;        // "name, kind (driver)": ComputeDevice::description()

    // As wavecam::illuminate_pinhole: the field at every sample, times its weight / lambda.
    Result<bool> illuminate_pinhole(const ApertureSamples& samples, const std::vector<PointSource>& sources,
                                    double wavelength, PinholeField& field, const ProgressFn& progress = {});
    // The same for several runs' weights at once (one dispatch); fields[r] receives run r's field.
    Result<bool> illuminate_pinhole_runs(const ApertureSamples& samples, const std::vector<PointSource>& sources,
                                         const RunWeights& run_weights, double wavelength,
                                         std::vector<PinholeField>& fields, const ProgressFn& progress = {});

    // As wavecam::add_film_field: adds the film field U(x) to film_field[t].
    Result<bool> add_film_field(const ApertureSamples& samples, const PinholeField& field, const FilmPoints& film,
                                double wavelength, std::complex<double>* film_field,
                                const ProgressFn& progress = {});
    // The same for several pinhole fields at once (one dispatch): adds run r's to film_fields[r].
    Result<bool> add_film_field_runs(const ApertureSamples& samples, const std::vector<PinholeField>& fields,
                                     const FilmPoints& film, double wavelength,
                                     const std::vector<std::complex<double>*>& film_fields,
                                     const ProgressFn& progress = {});

    struct Impl;

private:
    explicit GpuSums(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace wavecam
