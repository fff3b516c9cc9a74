// The pinhole samples on and off the lattice (lattice_layout.h).
#include "summation/nufft/lattice_layout.h"

#include <algorithm>
#include <climits>
#include <cmath>

namespace wavecam::detail {

bool on_lattice(const ApertureSamples& s, size_t k, long& i, long& j) {
    const double fx = s.x[k] / s.pitch, fy = s.y[k] / s.pitch;
    i = std::lround(fx), j = std::lround(fy);
    return std::abs(fx - i) < 1e-4 && std::abs(fy - j) < 1e-4;
}

LatticeLayout lattice_layout(const ApertureSamples& s, const BandLimitedStencil& stencil) {
    LatticeLayout L;
    const double h = s.pitch;
    L.off.pitch = h;
    const bool spread = stencil.usable();
    L.width = spread ? stencil.width() : 0;
    std::vector<long> im(s.size()), jm(s.size());
    long i0 = 0, i1 = -1, j0 = 0, j1 = -1;
    bool any = false;
    auto take = [&](long i, long j) {
        if (!any) i0 = i1 = i, j0 = j1 = j, any = true;
        i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
    };
    double wx[64], wy[64];
    for (size_t k = 0; k < s.size(); ++k) {
        long i, j;
        if (on_lattice(s, k, i, j)) {
            im[k] = i;
            jm[k] = j;
            take(i, j);
        } else if (spread) {
            const long si = stencil.weights(s.x[k] / h, wx), sj = stencil.weights(s.y[k] / h, wy);
            im[k] = si;
            jm[k] = sj;
            take(si, sj);
            take(si + L.width - 1, sj + L.width - 1);
            L.spread_index.push_back(k);
            L.spread_wx.insert(L.spread_wx.end(), wx, wx + L.width);
            L.spread_wy.insert(L.spread_wy.end(), wy, wy + L.width);
        } else {
            im[k] = LONG_MIN;
        }
    }
    L.i0 = i0, L.j0 = j0;
    L.nx = any ? int(i1 - i0 + 1) : 0;
    L.ny = any ? int(j1 - j0 + 1) : 0;
    L.cell.assign(s.size(), -1);
    L.used.assign(size_t(L.nx) * L.ny, 0);
    for (size_t k : L.spread_index) {
        const long first = (jm[k] - j0) * L.nx + (im[k] - i0);
        L.spread_cell.push_back(first);
        for (int b = 0; b < L.width; ++b)
            for (int a = 0; a < L.width; ++a) L.used[first + long(b) * L.nx + a] = 1;
        im[k] = LONG_MIN + 1;  // done
    }
    for (size_t k = 0; k < s.size(); ++k) {
        if (im[k] == LONG_MIN + 1) continue;
        if (im[k] == LONG_MIN) {
            L.off.x.push_back(s.x[k]);
            L.off.y.push_back(s.y[k]);
            L.off.weight.push_back(s.weight[k]);
            L.off_index.push_back(k);
            continue;
        }
        L.cell[k] = (jm[k] - j0) * L.nx + (im[k] - i0);
        L.used[L.cell[k]] = 1;
        ++L.on;
    }
    return L;
}

SampleCount count_samples(const ApertureSamples& s) {
    SampleCount c;
    for (size_t k = 0; k < s.size(); ++k) {
        long i, j;
        (on_lattice(s, k, i, j) ? c.on : c.off) += 1;
        c.reach = std::max(c.reach, std::hypot(double(s.x[k]), double(s.y[k])));
    }
    return c;
}

}  // namespace wavecam::detail
