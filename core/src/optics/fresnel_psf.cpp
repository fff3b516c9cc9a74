// The field PSF's entry points: the two evaluations of the Fresnel integral
// (wavecam/fresnel_psf.h), the matrix Fourier transform (fresnel_mft.cpp) and the transfer
// function (fresnel_transfer.cpp), the cheaper one chosen per request.
#include "wavecam/fresnel_psf.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "fft/column_fft.h"
#include "optics/fresnel_field.h"
#include "optics/fresnel_mft.h"
#include "optics/fresnel_transfer.h"

namespace wavecam {
namespace {
// A request's geometry, both evaluations' plans, and which of them serves it.
struct Evaluation {
    detail::FieldGeometry g;
    detail::MftPlan mft;
    detail::TransferPlan transfer;
    bool by_transfer = false;
};

Evaluation evaluation_of(const FieldPsfRequest& q) {
    Evaluation e;
    e.g = detail::geometry_of(q);
    e.mft = detail::plan_mft(q, e.g);
    e.transfer = detail::plan_transfer(q, e.g);
    e.by_transfer = q.method == FieldPsfMethod::TransferFunction ||
                    (q.method == FieldPsfMethod::Auto && q.pupil_samples <= 0 && e.transfer.cost() < e.mft.cost());
    return e;
}
}  // namespace

double field_psf_scratch_bytes(const FieldPsfRequest& q) {
    const Evaluation e = evaluation_of(q);
    const detail::MftPlan& mft = e.mft;
    const detail::TransferPlan& transfer = e.transfer;
    const double w = 2.0 * q.radius + 1;
    if (e.by_transfer) {
        // a block of columns and its work, the kernel's rows and their transform's work, the
        // forward transform's grid and work (a pupil even in x and y: its packed rows, packed
        // columns and their work, a quarter of the grid each), and the spectra kept per thread (a
        // point-symmetric pupil's: real, half the columns)
        const double n = transfer.n, rows = w * transfer.sub;
        const double kept = transfer.symmetric ? 4.0 * n * (n / 2 + 1) : 8.0 * n * n;
        return 8.0 * (2 * n * detail::ColumnFft::block_columns(transfer.n) + 2 * n * rows + (transfer.mirror_even ? 0.75 : 2) * n * n) +
               detail::kSpectraKept * kept + 8.0 * w * w;
    }
    const double pr = mft.kept(mft.nr), pt = mft.kept(mft.nt), m = mft.grid();
    // pupil cells, the two axis matrices and the intermediate (complex), the power grid, the
    // pixel averages' offsets and weights
    return 4.0 * (pr * pt + 2 * m * (pr + pt) + 2 * pr * m + m * m + 2 * m) + 8.0 * w * mft.points + 4.0 * w * w;
}

void share_transfer_grids(std::vector<FieldPsfRequest>& requests) {
    // (own grid, index) of the requests the transfer function serves on their own grids, widest first
    std::vector<std::pair<int, size_t>> own;
    for (size_t i = 0; i < requests.size(); ++i) {
        FieldPsfRequest& q = requests[i];
        q.transfer_grid = 0;
        const Evaluation e = evaluation_of(q);
        if (e.by_transfer) own.push_back({e.transfer.n, i});
    }
    std::sort(own.rbegin(), own.rend());
    for (size_t k = 0; k < own.size();) {
        const double top = own[k].first;
        size_t end = k;
        while (end < own.size() && top * top <= kSharedGridArea * own[end].first * double(own[end].first)) ++end;
        for (; k < end; ++k) requests[own[k].second].transfer_grid = int(top);
    }
}

PsfKernel field_psf_kernel(const FieldPsfRequest& q) {
    const Evaluation e = evaluation_of(q);
    PsfKernel k;
    k.radius = q.radius;
    k.weight = e.by_transfer ? detail::kernel_by_transfer(q, e.g, e.transfer) : detail::kernel_by_mft(q, e.g, e.mft);
    if (!e.by_transfer && e.mft.half * e.mft.step < (q.radius + 0.5) * q.pixel_pitch) k.reach = e.mft.half * e.mft.step;
    return k;
}

int psf_kernel_radius(const WidestPsf& psf, double pixel_pitch, int max_radius) {
    const double r =
        detail::psf_radius(psf.aperture, psf.film_distance, psf.nearest_depth, psf.wavelength, psf.cos_theta_max,
                           psf.energy) /
        pixel_pitch;
    return int(std::clamp(std::ceil(r), 1.0, double(max_radius)));  // (clamped as a double: no overflow)
}

}  // namespace wavecam
