// Sub-apertures of the pinhole lattice and their probe discs (sub_apertures.h).
#include "summation/nufft/sub_apertures.h"

#include <algorithm>
#include <cmath>

namespace wavecam::detail {

SubApertures split_lattice(const LatticeLayout& L, int blocks, double h) {
    SubApertures S;
    S.blocks = std::max(1, std::min({blocks, L.nx, L.ny}));
    S.bnx = (L.nx + S.blocks - 1) / S.blocks;
    S.bny = (L.ny + S.blocks - 1) / S.blocks;
    for (int by = 0; by < S.blocks; ++by)
        for (int bx = 0; bx < S.blocks; ++bx) {
            SubAperture a;
            a.i0 = L.i0 + long(bx) * S.bnx;
            a.j0 = L.j0 + long(by) * S.bny;
            a.cx = (a.i0 + 0.5 * (S.bnx - 1)) * h;
            a.cy = (a.j0 + 0.5 * (S.bny - 1)) * h;
            a.cells.assign(size_t(S.bnx) * S.bny, -1);
            bool any = false;
            for (int n = 0; n < S.bny; ++n)
                for (int m = 0; m < S.bnx; ++m) {
                    const long i = a.i0 + m - L.i0, j = a.j0 + n - L.j0;
                    if (i >= L.nx || j >= L.ny || !L.used[size_t(j) * L.nx + i]) continue;
                    a.cells[size_t(n) * S.bnx + m] = j * L.nx + i;
                    a.reach = std::max(a.reach, std::hypot((a.i0 + m) * h - a.cx, (a.j0 + n) * h - a.cy));
                    any = true;
                }
            a.reach += h;
            if (any) S.parts.push_back(std::move(a));
        }
    return S;
}

std::vector<ProbeDisc> discs_of(const SubApertures& S) {
    std::vector<ProbeDisc> d;
    for (const SubAperture& a : S.parts) d.push_back({a.cx, a.cy, a.reach});
    return d;
}

std::vector<ProbeDisc> probe_discs(const std::vector<ProbeDisc>& all) {
    std::vector<ProbeDisc> pick;
    if (all.empty()) return pick;
    auto best = [&](auto score) {
        size_t b = 0;
        for (size_t i = 1; i < all.size(); ++i)
            if (score(all[i]) > score(all[b])) b = i;
        return b;
    };
    std::vector<size_t> idx{best([](const ProbeDisc& d) { return -std::hypot(d.cx, d.cy); })};
    for (int sx : {-1, 1})
        for (int sy : {-1, 1}) idx.push_back(best([&](const ProbeDisc& d) { return sx * d.cx + sy * d.cy; }));
    std::sort(idx.begin(), idx.end());
    idx.erase(std::unique(idx.begin(), idx.end()), idx.end());
    for (size_t i : idx) pick.push_back(all[i]);
    return pick;
}

}  // namespace wavecam::detail
