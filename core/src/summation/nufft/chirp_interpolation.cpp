// The chirps' remainder interpolated over the points' parameters (chirp_interpolation.h).
#include "summation/nufft/chirp_interpolation.h"

#include <algorithm>
#include <cmath>

#include "base/parallel.h"

namespace wavecam::detail {

using cdouble = std::complex<double>;

ChebyshevBox ChirpGeometry::box(const DirectionRange& r) const {
    ChebyshevBox b;
    b.dims = film ? 2 : 3;
    b.lo = {r.ux0, r.uy0, r.rho0};
    b.hi = {r.ux1, r.uy1, r.rho1};
    return b;
}

std::vector<ChebyshevBox> ChirpGeometry::tiling(const DirectionRange& r, const std::vector<ProbeDisc>& discs,
                                              double* probed, double max_evaluations) const {
    std::vector<std::array<double, 4>> pr;  // centre, probe point: 8 directions at each disc's reach
    for (const ProbeDisc& d : probe_discs(discs))
        for (int a = 0; a < 8; ++a)
            pr.push_back({d.cx, d.cy, d.cx + d.reach * std::cos(a * M_PI / 4), d.cy + d.reach * std::sin(a * M_PI / 4)});
    double evaluations = 0;
    std::vector<ChebyshevBox> boxes = tile_boxes(
        box(r),
        [&](const Parameter& p, int i) {
            ++evaluations;
            return cdouble(at(p, pr[i][0], pr[i][1]).remainder(pr[i][2], pr[i][3], k / (2 * M_PI), power()));
        },
        int(pr.size()), {tolerance, kMaxRank, kMaxNodes, false, &evaluations, max_evaluations});
    if (probed) *probed = evaluations;
    return boxes;
}

ChirpGeometry chirp_geometry(bool film, double wavelength, double tolerance, const DirectionRange& range) {
    return {film, film ? 1.0 / std::max(range.rho1, 1e-9) : 0.0, 2 * M_PI / wavelength, tolerance};
}

AxisWeights::AxisWeights(const ChebyshevBox& b, const std::vector<Parameter>& p, const std::vector<size_t>& points,
                         int nthreads) {
    for (int d = 0; d < b.dims; ++d) {
        n[d] = b.nodes[d];
        offset[d] = stride;
        stride += n[d];
    }
    w.resize(points.size() * stride);
    parallel_for(0, long(points.size()), thread_count(nthreads), [&](int64_t i) {
        // the axis values from a one-axis box each (barycentric form, chebyshev_box.cpp)
        for (int d = 0; d < b.dims; ++d) {
            ChebyshevBox axis;
            axis.dims = 1;
            axis.lo[0] = b.lo[d];
            axis.hi[0] = b.hi[d];
            axis.nodes[0] = n[d];
            double v[16];
            axis.weights({p[points[i]][d], 0, 0}, v);
            for (int q = 0; q < n[d]; ++q) w[i * stride + offset[d] + q] = float(v[q]);
        }
    });
}

std::vector<std::vector<size_t>> group(const std::vector<ChebyshevBox>& boxes, const std::vector<Parameter>& p) {
    std::vector<std::vector<size_t>> g(boxes.size());
    for (size_t i = 0; i < p.size(); ++i) {
        size_t b = 0;
        while (b + 1 < boxes.size() && !boxes[b].contains(p[i])) ++b;
        g[b].push_back(i);
    }
    return g;
}

DirectionRange range_of(const std::vector<Parameter>& p, int dims) {
    DirectionRange r;
    if (p.empty()) return r;
    Parameter lo = p[0], hi = p[0];
    for (const Parameter& q : p)
        for (int d = 0; d < dims; ++d) lo[d] = std::min(lo[d], q[d]), hi[d] = std::max(hi[d], q[d]);
    r.ux0 = lo[0], r.ux1 = hi[0], r.uy0 = lo[1], r.uy1 = hi[1];
    if (dims > 2) r.rho0 = lo[2], r.rho1 = hi[2];
    return r;
}

NodeSkeleton box_skeleton(const ChirpGeometry& geo, const ChebyshevBox& bx, const ProbeDisc& d) {
    std::vector<std::array<double, 2>> at;
    for (int j = -5; j <= 5; ++j)
        for (int i = -5; i <= 5; ++i)
            if (i * i + j * j <= 25) at.push_back({d.cx + d.reach * i / 5.0, d.cy + d.reach * j / 5.0});
    for (int a = 0; a < 16; ++a) at.push_back({d.cx + d.reach * std::cos(a * M_PI / 8), d.cy + d.reach * std::sin(a * M_PI / 8)});
    const int rank = bx.rank(), n = int(at.size());
    std::vector<cdouble> v(size_t(rank) * n);
    for (int q = 0; q < rank; ++q) {
        const ChirpAtCentre c = geo.at(bx.node(q), d.cx, d.cy);
        for (int i = 0; i < n; ++i)
            v[size_t(q) * n + i] = cdouble(c.remainder(at[i][0], at[i][1], geo.k / (2 * M_PI), geo.power()));
    }
    return node_skeleton(v, rank, n, geo.tolerance / 4);
}

}  // namespace wavecam::detail
