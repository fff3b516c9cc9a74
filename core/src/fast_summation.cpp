// The fast summation of the exact method's two sums (wavecam/fast_summation.h,
// docs/fast_summation.md).
//
// Path from a point at distance R along the unit direction u (in-plane components u) to a pinhole
// point xi (z = 0), exactly, with rho = 1/R and g = r / R:
//   g^2 = 1 - 2 rho u.xi + rho^2 |xi|^2,
//   r - R = (rho |xi|^2 - 2 u.xi) / (1 + g)                    (no cancellation),
//   psi = r - R + u.xi = rho (|xi|^2 + u.xi (rho |xi|^2 - 2 u.xi) / (1 + g)) / (1 + g),
// psi ~ rho (|xi|^2 - (u.xi)^2) / 2: the chirp, smooth in (u, rho). Sources: U(xi) = sum_s
// (c_s / R_s) exp(-i k u_s.xi) [exp(i k psi) / g]; film: U(t) = (f / R_t^2) sum_xi w(xi)
// exp(-i k n_t.xi) [exp(i k psi) / g^2], n_t = t / R_t, 1 / R_t = sqrt(1 - |n_t|^2) / f.
#include "wavecam/fast_summation.h"

#include <omp.h>

#include <algorithm>
#include <climits>
#include <mutex>
#include <cstdlib>
#include <string>
#include <cmath>

#include "band_limited_stencil.h"
#include "chebyshev_box.h"
#include "lattice_nufft.h"
#include "node_skeleton.h"
#include "sincos_turns.h"

namespace wavecam {
namespace {

using detail::cfloat;
using detail::ChebyshevBox;
using detail::Parameter;
using cdouble = std::complex<double>;

// The path's chirp at (x, y) for direction (ux, uy), inverse distance rho: psi and g = r / R.
struct Chirp {
    double psi, g;
};
inline Chirp chirp(double ux, double uy, double rho, double x, double y) {
    const double q2 = x * x + y * y, p = ux * x + uy * y;
    const double g = std::sqrt(std::max(1e-300, 1.0 - 2.0 * rho * p + rho * rho * q2));
    return {rho * (q2 + p * (rho * q2 - 2.0 * p) / (1.0 + g)) / (1.0 + g), g};
}

// The chirp's expansion about a sub-aperture's centre c: psi(xi) = psi(c) + grad psi(c).(xi - c)
// + psi2(xi), grad psi = (rho xi + (g - 1) u) / g (from d r / d xi = (xi - R u) / r). The first
// two terms are exact per point (a phase and a shift of its frequency); psi2, quadratic in
// xi - c, is what the nodes interpolate: over a sub-aperture of 1/B the width it varies B^2 less.
struct ChirpAtCentre {
    double psi, gx, gy, cx, cy, rho, ux, uy;
    ChirpAtCentre(double ux_, double uy_, double rho_, double cx_, double cy_)
        : cx(cx_), cy(cy_), rho(rho_), ux(ux_), uy(uy_) {
        const Chirp c = chirp(ux, uy, rho, cx, cy);
        const double q2 = cx * cx + cy * cy, p = ux * cx + uy * cy;
        const double gm1 = rho * (rho * q2 - 2.0 * p) / (1.0 + c.g);  // g - 1 without cancellation
        psi = c.psi;
        gx = (rho * cx + gm1 * ux) / c.g;
        gy = (rho * cy + gm1 * uy) / c.g;
    }
    // exp(i k psi2(x, y)) / g^power: the interpolated remainder (k psi2 a few radians at most:
    // its sine and cosine in float, sincos_turns.h, to about 1e-6).
    cfloat remainder(double x, double y, double inv_lambda, int power) const {
        const Chirp c = chirp(ux, uy, rho, x, y);
        const double psi2 = c.psi - psi - gx * (x - cx) - gy * (y - cy);
        float sn, cs;
        detail::sincos_turns(float(psi2 * inv_lambda), sn, cs);
        const float a = float(power == 1 ? 1.0 / c.g : 1.0 / (c.g * c.g));
        return {a * cs, a * sn};
    }
};

// The pinhole samples split into the lattice box they sit on (cell centres m h, n h) and the
// rest (rim centroids, grey or holed apertures). The rest are read from (sum 1) or spread onto
// (sum 2) the lattice around them with the band-limited stencil where the sum's band allows
// (band_limited_stencil.h; the box then takes in their stencils' cells), else summed directly.
struct LatticeLayout {
    long i0 = 0, j0 = 0;
    int nx = 0, ny = 0;
    std::vector<long> cell;          // per sample: (n - j0) * nx + (m - i0), or -1 off the lattice
    std::vector<char> used;          // per lattice cell: a sample or a stencil sits there
    ApertureSamples off;             // off-lattice samples summed directly
    std::vector<size_t> off_index;   // their indices in the samples
    size_t on = 0;                   // lattice samples
    // off-lattice samples through the stencil: their indices, their stencil's first cell, and
    // `width` weights per axis each
    std::vector<size_t> spread_index;
    std::vector<long> spread_cell;
    std::vector<double> spread_wx, spread_wy;
    int width = 0;
};

// Whether sample k sits on the lattice, and at which cell: a float position within 1e-4 pitch of a
// cell centre is that cell's centre.
inline bool on_lattice(const ApertureSamples& s, size_t k, long& i, long& j) {
    const double fx = s.x[k] / s.pitch, fy = s.y[k] / s.pitch;
    i = std::lround(fx), j = std::lround(fy);
    return std::abs(fx - i) < 1e-4 && std::abs(fy - j) < 1e-4;
}

LatticeLayout lattice_layout(const ApertureSamples& s, const detail::BandLimitedStencil& stencil) {
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

// No stencil: every off-lattice sample summed directly.
detail::BandLimitedStencil no_stencil() { return {M_PI, 1e-2}; }

// The stencil for a band and error per term; a stencil's choice takes milliseconds and every sum
// of a frame asks alike: the last few are kept.
detail::BandLimitedStencil stencil_for(double band, double per_term) {
    static std::mutex lock;
    static std::vector<std::pair<std::array<double, 2>, detail::BandLimitedStencil>> known;
    std::lock_guard<std::mutex> guard(lock);
    for (const auto& [key, stencil] : known)
        if (key[0] == band && key[1] == per_term) return stencil;
    if (known.size() >= 16) known.erase(known.begin());
    known.push_back({{band, per_term}, detail::BandLimitedStencil(band, per_term)});
    return known.back().second;
}

// The stencil for a sum over `range` (lattice pitch h, samples within `reach` of the axis), and
// the points it serves: those whose direction components stay within `inner` on both axes.
// A point's band is k h times its largest direction component plus the chirp's slope |grad psi|
// <= 2 rho reach (ChirpAtCentre). The stencil's error is on the off-lattice samples' terms only:
// a share off / (on + off) of the sum (rim cells, about 4 / samples across), so the sum keeps
// within a third of the tolerance, relative to the sum of its terms' sizes, with each of those
// terms within tolerance / 3 x (on + off) / off, at most 1e-2. Where the range's band is too wide
// (a frame's margin of sources beyond a lattice sized for the frame), the widest band the stencil
// serves: the points beyond take the direct terms for their off-lattice samples.
struct StencilChoice {
    detail::BandLimitedStencil stencil = no_stencil();
    double inner = -1;  // largest direction component served (inf: every point; < 0: none)
};
StencilChoice choose_stencil(const DirectionRange& r, double k, double h, double reach, double on, double off,
                             double tolerance) {
    const double u = std::max({std::fabs(r.ux0), std::fabs(r.ux1), std::fabs(r.uy0), std::fabs(r.uy1)});
    const double slope = 2 * std::max(std::fabs(r.rho0), std::fabs(r.rho1)) * reach;
    const double per_term = std::min(1e-2, tolerance / 3 * (on + off) / std::max(1.0, off));
    const double band = k * h * (u + slope);
    StencilChoice c;
    if (band < M_PI) c.stencil = stencil_for(band, per_term);
    if (c.stencil.usable()) {
        c.inner = INFINITY;
        return c;
    }
    for (double narrower : {0.9, 0.8, 0.7, 0.6, 0.5}) {
        if (narrower * M_PI >= band) continue;
        c.stencil = stencil_for(narrower * M_PI, per_term);
        if (c.stencil.usable()) {
            c.inner = narrower * M_PI / (k * h) - slope;
            return c;
        }
    }
    return c;
}

// Whether a point (in-plane direction components) is within the stencil's reach.
inline bool within(double inner, double ux, double uy) { return std::max(std::fabs(ux), std::fabs(uy)) <= inner; }

// Samples on the lattice and off it (as lattice_layout tells them), and the farthest from the axis.
struct SampleCount {
    double on = 0, off = 0, reach = 0;
};
SampleCount count_samples(const ApertureSamples& s) {
    SampleCount c;
    for (size_t k = 0; k < s.size(); ++k) {
        long i, j;
        (on_lattice(s, k, i, j) ? c.on : c.off) += 1;
        c.reach = std::max(c.reach, std::hypot(double(s.x[k]), double(s.y[k])));
    }
    return c;
}

// The lattice box cut into B x B sub-apertures of bnx x bny cells (the last row and column of
// them may overhang the box), each expanded about its centre; those holding no sample dropped.
struct SubAperture {
    long i0 = 0, j0 = 0;        // its first cell, in lattice indices
    double cx = 0, cy = 0;      // the expansion centre (metres)
    double reach = 0;           // farthest sample from the centre, plus a cell: the probes' reach
    std::vector<long> cells;    // per local cell n * bnx + m: the layout's cell, or -1
};
struct SubApertures {
    int blocks = 1, bnx = 0, bny = 0;
    std::vector<SubAperture> parts;
};

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

// Where the remainder is probed to choose the nodes: 8 directions at the reach of the central
// sub-aperture and of the four outermost along the diagonals (the Hessian of psi, hence psi2,
// changes a little across the pinhole; one plan serves every sub-aperture).
struct ProbeDisc {
    double cx, cy, reach;
};
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

double film_rho(double nx, double ny, double f) { return std::sqrt(std::max(0.0, 1.0 - nx * nx - ny * ny)) / f; }

// The boxes of one sum: sources (3 parameters ux, uy, rho; chirp / g) or film points (2: nx, ny;
// rho from the film distance; chirp / g^2).
struct SumGeometry {
    bool film = false;
    double f = 0, k = 0, tolerance = kSummationTolerance;
    int power() const { return film ? 2 : 1; }
    int dims() const { return film ? 2 : 3; }
    ChebyshevBox box(const DirectionRange& r) const {
        ChebyshevBox b;
        b.dims = film ? 2 : 3;
        b.lo = {r.ux0, r.uy0, r.rho0};
        b.hi = {r.ux1, r.uy1, r.rho1};
        return b;
    }
    ChirpAtCentre at(const Parameter& p, double cx, double cy) const {
        return {p[0], p[1], film ? film_rho(p[0], p[1], f) : p[2], cx, cy};
    }
    std::vector<ChebyshevBox> plan(const DirectionRange& r, const std::vector<ProbeDisc>& discs) const {
        std::vector<std::array<double, 4>> pr;  // centre, probe point
        for (const ProbeDisc& d : probe_discs(discs))
            for (int a = 0; a < 8; ++a)
                pr.push_back({d.cx, d.cy, d.cx + d.reach * std::cos(a * M_PI / 4), d.cy + d.reach * std::sin(a * M_PI / 4)});
        return detail::plan_boxes(
            box(r),
            [&](const Parameter& p, int i) { return cdouble(at(p, pr[i][0], pr[i][1]).remainder(pr[i][2], pr[i][3], k / (2 * M_PI), power())); },
            int(pr.size()), tolerance, kMaxRank, kMaxNodes, false);
    }
    // Split only where an axis needs more than kMaxNodes: the nodes' count costs only per-point
    // arithmetic, the transforms are the skeleton's (node_skeleton.h).
    static constexpr int kMaxRank = 4096, kMaxNodes = 12;
};

// Per-axis Lagrange values of each point in a box, so that node q's weight is a product of three.
struct AxisWeights {
    std::array<int, 3> n{1, 1, 1}, offset{0, 0, 0};
    int stride = 0;
    std::vector<float> w;  // point-major, stride values per point
    AxisWeights(const ChebyshevBox& b, const std::vector<Parameter>& p, const std::vector<size_t>& points) {
        for (int d = 0; d < b.dims; ++d) {
            n[d] = b.nodes[d];
            offset[d] = stride;
            stride += n[d];
        }
        w.resize(points.size() * stride);
#pragma omp parallel for schedule(static)
        for (long i = 0; i < long(points.size()); ++i) {
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
        }
    }
    double at(size_t i, int q, int dims) const {
        double v = 1;
        for (int d = 0; d < dims; ++d) {
            v *= w[i * stride + offset[d] + q % n[d]];
            q /= n[d];
        }
        return v;
    }
};

// Points grouped by the first box holding them (the boxes tile the range; a point on a shared
// face goes to the first).
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

int threads(int n) { return n > 0 ? n : omp_get_max_threads(); }

// Cost of the fast path's parts in direct terms (one term of propagation.cpp's kernel, 1.5 ns on
// this machine's 2 cores), measured here on a 620 x 620 lattice with 400k points in scan order:
// an FFT point x log2 2.0 ns, a kernel tap 4.3 ns (with the point's weights and phase), a chirp
// 22 ns (double sqrt and sincos). The ratios, not the times, are what the estimate uses.
constexpr double kFftCost = 1.33, kTapCost = 2.9, kChirpCost = 15.0;
// A complex multiply-add in double, a third of a term.
constexpr double kMacCost = 0.35;

// Per point for one sub-aperture: the NUFFT frequency k h (u - grad psi(c)) (radians per lattice
// step) and the phase exp(i k (psi(c) - grad psi(c).c)) times the lattice-start phase of the
// sub-aperture's first cell (i0, j0) and the NUFFT's centring, applied once per point.
struct SubApertureFrequencies {
    std::vector<double> fx, fy;
    std::vector<cdouble> shift;
    SubApertureFrequencies(const std::vector<size_t>& in, const std::vector<Parameter>& p, const SumGeometry& geo,
                           const SubAperture& a, double h, const detail::LatticeNufft& nufft, int nthreads)
        : fx(in.size()), fy(in.size()), shift(in.size()) {
        const double k = geo.k;
#pragma omp parallel for schedule(static) num_threads(threads(nthreads))
        for (long i = 0; i < long(in.size()); ++i) {
            const Parameter& q = p[in[i]];
            const ChirpAtCentre c = geo.at(q, a.cx, a.cy);
            fx[i] = k * h * (q[0] - c.gx);
            fy[i] = k * h * (q[1] - c.gy);
            shift[i] = std::polar(1.0, k * (c.psi - c.gx * a.cx - c.gy * a.cy) - (fx[i] * a.i0 + fy[i] * a.j0) +
                                           nufft.centring_phase(fx[i], fy[i]));
        }
    }
};

// Transforms run in batches of up to this many interpolation nodes: a point's kernel weights are
// computed once per batch, at the memory of this many grids.
constexpr int kBatch = 8;

// The lattice cells of a sub-aperture in metres: local cell c = n * bnx + m.
inline double cell_x(const SubAperture& a, const SubApertures& S, long c, double h) { return (a.i0 + c % S.bnx) * h; }
inline double cell_y(const SubAperture& a, const SubApertures& S, long c, double h) { return (a.j0 + c / S.bnx) * h; }

std::vector<ProbeDisc> discs_of(const SubApertures& S) {
    std::vector<ProbeDisc> d;
    for (const SubAperture& a : S.parts) d.push_back({a.cx, a.cy, a.reach});
    return d;
}

// A box's skeleton on one sub-aperture: its nodes' remainders fitted at an 11 x 11 grid over the
// sub-aperture's disc and 16 points on its rim, to a quarter of the tolerance (the Lagrange
// weights' sum of magnitudes, a few, multiplies it; the interpolation's own and the NUFFT's error
// are the rest of the budget).
detail::NodeSkeleton box_skeleton(const SumGeometry& geo, const ChebyshevBox& bx, const ProbeDisc& d) {
    std::vector<std::array<double, 2>> at;
    for (int j = -5; j <= 5; ++j)
        for (int i = -5; i <= 5; ++i)
            if (i * i + j * j <= 25) at.push_back({d.cx + d.reach * i / 5.0, d.cy + d.reach * j / 5.0});
    for (int a = 0; a < 16; ++a) at.push_back({d.cx + d.reach * std::cos(a * M_PI / 8), d.cy + d.reach * std::sin(a * M_PI / 8)});
    const int rank = bx.rank(), n = int(at.size());
    std::vector<cdouble> v(size_t(rank) * n);
    for (int q = 0; q < rank; ++q) {
        const ChirpAtCentre c = geo.at(bx.node(q), d.cx, d.cy);
        for (int i = 0; i < n; ++i) v[size_t(q) * n + i] = cdouble(c.remainder(at[i][0], at[i][1], geo.k / (2 * M_PI), geo.power()));
    }
    return detail::node_skeleton(v, rank, n, geo.tolerance / 4);
}

// One point's coefficients on up to kBatch skeleton nodes: sum_k L[k] (tr + i ti)[k][q] (the
// skeleton's coefficients split into real and imaginary, padded to kBatch: one vector of eight
// per node, written so with GCC's vector extension).
typedef float Eight __attribute__((vector_size(32)));
static_assert(kBatch * sizeof(float) == sizeof(Eight));
__attribute__((target_clones("arch=x86-64-v3", "default")))
void node_sums(const float* L, int nodes, const Eight* tr, const Eight* ti, Eight& out_re, Eight& out_im) {
    Eight ar = {}, ai = {};
    for (int k = 0; k < nodes; ++k) {
        ar += L[k] * tr[k];
        ai += L[k] * ti[k];
    }
    out_re = ar;
    out_im = ai;
}

// Each point's coefficients on skeleton nodes j0 .. j0 + batch - 1, sum_q L_q(p) coeff[q][j],
// times factor[i] if given, into out[i * batch + j - j0] (L_q a product of per-axis values, axis 0
// fastest).
void skeleton_coefficients(const AxisWeights& aw, int dims, const detail::NodeSkeleton& sk, int j0, int batch,
                           size_t count, int nodes, const cdouble* factor, std::vector<cfloat>& out, int nthreads) {
    const int r = sk.rank();
    std::vector<Eight> re(nodes), im(nodes);
    for (int k = 0; k < nodes; ++k)
        for (int q = 0; q < kBatch; ++q) {
            const cdouble t = q < batch ? sk.coeff[size_t(k) * r + j0 + q] : 0.0;
            re[k][q] = float(t.real());
            im[k][q] = float(t.imag());
        }
    out.resize(count * batch);
    const int n0 = aw.n[0], n1 = dims > 1 ? aw.n[1] : 1, n2 = dims > 2 ? aw.n[2] : 1;
#pragma omp parallel num_threads(threads(nthreads))
    {
        std::vector<float> L(nodes);
        Eight sr, si;
#pragma omp for schedule(static)
        for (long i = 0; i < long(count); ++i) {
            const float* w = aw.w.data() + size_t(i) * aw.stride;
            int q = 0;
            for (int c = 0; c < n2; ++c)
                for (int b = 0; b < n1; ++b) {
                    const float lbc = (dims > 1 ? w[aw.offset[1] + b] : 1.0f) * (dims > 2 ? w[aw.offset[2] + c] : 1.0f);
                    for (int a = 0; a < n0; ++a) L[q++] = lbc * w[aw.offset[0] + a];
                }
            node_sums(L.data(), nodes, re.data(), im.data(), sr, si);
            cfloat* o = out.data() + size_t(i) * batch;
            if (factor)
                for (int j = 0; j < batch; ++j) o[j] = cfloat(factor[i] * cdouble(sr[j], si[j]));
            else
                for (int j = 0; j < batch; ++j) o[j] = cfloat(sr[j], si[j]);
        }
    }
}

// What both fast sums walk: for every sub-aperture and every parameter box holding points, the
// points' frequencies and phases there and the box's skeleton, in batches of up to kBatch
// skeleton nodes; `batch_of(part, bi, fr, sk, j0, batch)` does a batch's transforms. Progress
// counts the boxes' nodes; false if cancelled.
template <class Batch>
bool walk_sub_apertures(const SubApertures& S, const SumGeometry& geo, const std::vector<Parameter>& p,
                        const DirectionRange& range, double h, const SummationSettings& set,
                        const ProgressFn& progress, const Batch& batch_of) {
    const std::vector<ChebyshevBox> boxes = geo.plan(range, discs_of(S));
    const auto members = group(boxes, p);
    std::vector<AxisWeights> weights;
    for (size_t bi = 0; bi < boxes.size(); ++bi) weights.emplace_back(boxes[bi], p, members[bi]);
    const detail::LatticeNufft nufft(S.bnx, S.bny, set.tolerance, set.nthreads);
    double total = 0, done = 0;
    for (const ChebyshevBox& bx : boxes) total += double(bx.rank()) * S.parts.size();
    for (const SubAperture& part : S.parts)
        for (size_t bi = 0; bi < boxes.size(); ++bi) {
            const ChebyshevBox& bx = boxes[bi];
            const std::vector<size_t>& in = members[bi];
            const detail::NodeSkeleton sk =
                in.empty() ? detail::NodeSkeleton{} : box_skeleton(geo, bx, {part.cx, part.cy, part.reach});
            const int r = sk.rank();
            if (r == 0) {
                done += bx.rank();
                continue;
            }
            const SubApertureFrequencies fr(in, p, geo, part, h, nufft, set.nthreads);
            for (int j0 = 0; j0 < r; j0 += kBatch) {
                const int batch = std::min(kBatch, r - j0);
                batch_of(part, in, weights[bi], bx, nufft, fr, sk, j0, batch);
                done += double(bx.rank()) * batch / r;
                if (progress && !progress(done / total)) return false;
            }
        }
    return true;
}

// Fast sum 1 over the lattice samples: U at every lattice cell (0 elsewhere).
bool fast_sources_to_lattice(const LatticeLayout& L, const ApertureSamples& samples,
                             const std::vector<PointSource>& sources, double wavelength, int blocks,
                             const SummationSettings& set, std::vector<cdouble>& U, const ProgressFn& progress) {
    const double k = 2 * M_PI / wavelength, h = samples.pitch;
    std::vector<Parameter> p(sources.size());
    std::vector<cdouble> b(sources.size());
    for (size_t s = 0; s < sources.size(); ++s) {
        const PointSource& src = sources[s];
        const cdouble c = std::polar(src.amplitude, src.phase);
        if (src.at_infinity) {
            p[s] = {src.x, src.y, 0.0};
            b[s] = c;
        } else {
            const double R = std::sqrt(src.x * src.x + src.y * src.y + src.z * src.z);
            p[s] = {src.x / R, src.y / R, 1.0 / R};
            b[s] = c / R;
        }
    }
    const SubApertures S = split_lattice(L, blocks, h);
    const SumGeometry geo{false, 0, k, set.tolerance};
    U.assign(size_t(L.nx) * L.ny, 0.0);
    const size_t cells = size_t(S.bnx) * S.bny;
    std::vector<std::vector<cfloat>> lattice(kBatch, std::vector<cfloat>(cells));
    std::vector<cfloat*> out(kBatch);
    for (int q = 0; q < kBatch; ++q) out[q] = lattice[q].data();
    std::vector<cdouble> base;
    std::vector<cfloat> a;
    return walk_sub_apertures(
        S, geo, p, set.fixed_range ? set.range : range_of(p, 3), h, set, progress,
        [&](const SubAperture& part, const std::vector<size_t>& in, const AxisWeights& weights,
            const ChebyshevBox& bx, const detail::LatticeNufft& nufft, const SubApertureFrequencies& fr,
            const detail::NodeSkeleton& sk, int j0, int batch) {
            if (j0 == 0) {
                base.resize(in.size());
                for (size_t i = 0; i < in.size(); ++i) base[i] = b[in[i]] * fr.shift[i];
            }
            skeleton_coefficients(weights, 3, sk, j0, batch, in.size(), bx.rank(), base.data(), a, set.nthreads);
            nufft.to_lattice(fr.fx.data(), fr.fy.data(), a.data(), batch, in.size(), out.data());
            for (int q = 0; q < batch; ++q) {
                const ChirpAtCentre node = geo.at(bx.node(sk.rows[j0 + q]), part.cx, part.cy);
                const cfloat* F = lattice[q].data();
#pragma omp parallel for schedule(static) num_threads(threads(set.nthreads))
                for (long c = 0; c < long(cells); ++c)
                    if (part.cells[c] >= 0)
                        U[part.cells[c]] +=
                            cdouble(node.remainder(cell_x(part, S, c, h), cell_y(part, S, c, h), 1 / wavelength, 1) * F[c]);
            }
        });
}

// Fast sum 2 from the lattice samples' field to every film point, added to `out`.
bool fast_lattice_to_film(const LatticeLayout& L, const ApertureSamples& samples, const PinholeField& field,
                          const FilmPoints& film, double wavelength, int blocks, const SummationSettings& set,
                          cdouble* out, const ProgressFn& progress) {
    const double k = 2 * M_PI / wavelength, h = samples.pitch, f = film.film_distance;
    std::vector<Parameter> p(film.size());
    for (size_t t = 0; t < film.size(); ++t) {
        const double tx = film.x[t], ty = film.y[t], R = std::sqrt(tx * tx + ty * ty + f * f);
        p[t] = {tx / R, ty / R, 0.0};
    }
    std::vector<cfloat> w(size_t(L.nx) * L.ny, cfloat(0));
    for (size_t j = 0; j < samples.size(); ++j)
        if (L.cell[j] >= 0) w[L.cell[j]] = cfloat(field.re[j], field.im[j]);
    // the stencil's samples spread onto the cells around them
    for (size_t i = 0; i < L.spread_index.size(); ++i) {
        const size_t j = L.spread_index[i];
        const std::complex<double> v(field.re[j], field.im[j]);
        for (int b = 0; b < L.width; ++b)
            for (int a = 0; a < L.width; ++a)
                w[L.spread_cell[i] + long(b) * L.nx + a] +=
                    cfloat(v * (L.spread_wx[i * L.width + a] * L.spread_wy[i * L.width + b]));
    }
    const SubApertures S = split_lattice(L, blocks, h);
    const SumGeometry geo{true, f, k, set.tolerance};
    const size_t cells = size_t(S.bnx) * S.bny;
    std::vector<std::vector<cfloat>> g(kBatch, std::vector<cfloat>(cells));
    std::vector<const cfloat*> lattices(kBatch);
    for (int q = 0; q < kBatch; ++q) lattices[q] = g[q].data();
    std::vector<cfloat> G, coeff;
    return walk_sub_apertures(
        S, geo, p, set.fixed_range ? set.range : range_of(p, 2), h, set, progress,
        [&](const SubAperture& part, const std::vector<size_t>& in, const AxisWeights& weights,
            const ChebyshevBox& bx, const detail::LatticeNufft& nufft, const SubApertureFrequencies& fr,
            const detail::NodeSkeleton& sk, int j0, int batch) {
            for (int q = 0; q < batch; ++q) {
                const ChirpAtCentre node = geo.at(bx.node(sk.rows[j0 + q]), part.cx, part.cy);
                cfloat* gq = g[q].data();
#pragma omp parallel for schedule(static) num_threads(threads(set.nthreads))
                for (long c = 0; c < long(cells); ++c)
                    gq[c] = part.cells[c] >= 0
                                ? w[part.cells[c]] *
                                      node.remainder(cell_x(part, S, c, h), cell_y(part, S, c, h), 1 / wavelength, 2)
                                : cfloat(0);
            }
            skeleton_coefficients(weights, 2, sk, j0, batch, in.size(), bx.rank(), nullptr, coeff, set.nthreads);
            G.resize(in.size());
            nufft.from_lattice(lattices.data(), batch, fr.fx.data(), fr.fy.data(), coeff.data(), in.size(), G.data());
#pragma omp parallel for schedule(static) num_threads(threads(set.nthreads))
            for (long i = 0; i < long(in.size()); ++i) {
                const double tx = film.x[in[i]], ty = film.y[in[i]];
                out[in[i]] += f / (tx * tx + ty * ty + f * f) * fr.shift[i] * cdouble(G[i]);  // f / R_t^2
            }
        });
}

// The fast path's work in direct terms for one division into sub-apertures (`discs`, each of
// bnx x bny cells): per sub-aperture and skeleton node an FFT and a lattice of chirps; per point
// and sub-aperture its frequency and phase, its skeleton coefficients and each skeleton node's
// kernel taps; the off-lattice samples direct. Skeleton ranks from the probed sub-apertures.
SummationWork fast_work(const SumGeometry& geo, const DirectionRange& range, const std::vector<ProbeDisc>& discs,
                        int bnx, int bny, double lattice_samples, double off_lattice, double points) {
    SummationWork w;
    const std::vector<ChebyshevBox> boxes = geo.plan(range, discs);
    const std::vector<ProbeDisc> probed = probe_discs(discs);
    const detail::LatticeNufft nufft(bnx, bny, geo.tolerance, 1);
    const double parts = double(discs.size()), dims = geo.dims();
    // each point meets one box (in proportion to its volume): its skeleton's taps and coefficients
    double transforms = 0, point_work = 0, volume = 0;
    for (const ChebyshevBox& b : boxes) {
        double v = 1, rank = 0;
        for (int d = 0; d < b.dims; ++d) v *= std::max(b.hi[d] - b.lo[d], 1e-12);
        for (const ProbeDisc& d : probed) rank += box_skeleton(geo, b, d).rank();
        rank /= double(probed.size());
        volume += v;
        point_work += v * (rank * kTapCost * nufft.taps_per_point() + b.rank() * (rank + dims) * kMacCost);
        transforms += rank;
    }
    w.nufft_count = int(std::lround(transforms * parts));
    w.fast = transforms * (parts * kFftCost * nufft.fft_work() + kChirpCost * lattice_samples) +
             points * parts * (point_work / volume + 2 * kChirpCost) + off_lattice * points;
    return w;
}

// Sub-apertures per side tried: while each keeps at least this many cells across.
constexpr int kMinCellsAcross = 24;
constexpr int kMaxBlocks = 16;

// The cheapest division (blocks per side) from `discs_for(blocks, bnx, bny)`: 1, 2, 4, ... while
// the work falls.
template <class Discs>
SummationWork cheapest_division(const SumGeometry& geo, const DirectionRange& range, int nx, int ny,
                                double lattice_samples, double off_lattice, double points, const Discs& discs_for) {
    SummationWork best;
    for (int blocks = 1; blocks <= kMaxBlocks; blocks *= 2) {
        const int bnx = (nx + blocks - 1) / blocks, bny = (ny + blocks - 1) / blocks;
        if (blocks > 1 && std::min(bnx, bny) < kMinCellsAcross) break;
        SummationWork w = fast_work(geo, range, discs_for(blocks), bnx, bny, lattice_samples, off_lattice, points);
        w.blocks = blocks;
        if (blocks > 1 && w.fast >= best.fast) break;
        best = w;
    }
    return best;
}

SumGeometry geometry_of(bool film, double wavelength, double tolerance, const DirectionRange& range) {
    // the film's distance: 1/R on axis
    return {film, film ? 1.0 / std::max(range.rho1, 1e-9) : 0.0, 2 * M_PI / wavelength, tolerance};
}

// The work of a sum on this lattice, its sub-apertures as they are.
SummationWork work_of(const LatticeLayout& L, double h, double points, const DirectionRange& r, double wavelength,
                      bool film, double tolerance) {
    const double cells = double(std::count(L.used.begin(), L.used.end(), char(1)));
    const double spread = double(L.spread_index.size());
    SummationWork w = cheapest_division(geometry_of(film, wavelength, tolerance, r), r, L.nx, L.ny, cells,
                                        double(L.off.size()), points,
                                        [&](int blocks) { return discs_of(split_lattice(L, blocks, h)); });
    w.fast += spread * L.width * L.width * kMacCost;
    w.direct = (double(L.on) + spread + double(L.off.size())) * points;
    return w;
}

SummationWork plan_work(double lattice_samples, int samples_across, double off_lattice, double points,
                        const DirectionRange& range, double aperture_radius, double wavelength, bool film,
                        double tolerance);

}  // namespace

SummationWork summation_work(double lattice_samples, int samples_across, double off_lattice, double points,
                             const DirectionRange& range, double aperture_radius, double wavelength, bool film,
                             double tolerance) {
    // The plans behind an estimate take tens of milliseconds; a frame asks the same several times
    // (the estimate, then each channel): the last few answers are kept.
    using Key = std::array<double, 14>;
    static std::mutex lock;
    static std::vector<std::pair<Key, SummationWork>> known;
    const Key key{lattice_samples, double(samples_across), off_lattice, points, range.ux0, range.ux1, range.uy0,
                  range.uy1, range.rho0, range.rho1, aperture_radius, wavelength, film ? 1.0 : 0.0, tolerance};
    {
        std::lock_guard<std::mutex> guard(lock);
        for (const auto& [k, v] : known)
            if (k == key) return v;
    }
    const SummationWork w = plan_work(lattice_samples, samples_across, off_lattice, points, range, aperture_radius,
                                      wavelength, film, tolerance);
    std::lock_guard<std::mutex> guard(lock);
    if (known.size() >= 32) known.erase(known.begin());
    known.emplace_back(key, w);
    return w;
}

namespace {

SummationWork plan_work(double lattice_samples, int samples_across, double off_lattice, double points,
                        const DirectionRange& range, double aperture_radius, double wavelength, bool film,
                        double tolerance) {
    SummationWork w;
    w.direct = (lattice_samples + off_lattice) * points;
    if (lattice_samples <= 0 || samples_across < 1) {
        w.fast = w.direct;
        return w;
    }
    // sub-apertures of a disc of radius a on a lattice of n cells across, pitch h: those whose
    // square meets the disc, reach half their diagonal and a cell
    const int n = samples_across;
    const double a = aperture_radius, h = 2 * a / std::max(1, n - 1);
    auto discs_for = [&](int blocks) {
        std::vector<ProbeDisc> d;
        const int bn = (n + blocks - 1) / blocks;
        const double side = bn * h;
        for (int by = 0; by < blocks; ++by)
            for (int bx = 0; bx < blocks; ++bx) {
                const double x0 = -a - 0.5 * h + bx * side, y0 = -a - 0.5 * h + by * side;
                const double nxp = std::clamp(0.0, x0, x0 + side), nyp = std::clamp(0.0, y0, y0 + side);
                if (std::hypot(nxp, nyp) > a) continue;
                // reach: the farthest of a 9 x 9 grid over the square that lies in the disc
                const double cx = x0 + 0.5 * side, cy = y0 + 0.5 * side;
                double reach = 0;
                for (int j = 0; j <= 8; ++j)
                    for (int i = 0; i <= 8; ++i) {
                        const double x = x0 + side * i / 8, y = y0 + side * j / 8;
                        if (std::hypot(x, y) <= a + h) reach = std::max(reach, std::hypot(x - cx, y - cy));
                    }
                d.push_back({cx, cy, reach + h});
            }
        return d;
    };
    // off-lattice samples through the stencil where the band allows: their stencils' cells join
    // the lattice (about one row of `width` per rim sample), their spreading costs little; points
    // beyond its reach (as a share of the range's area) take them directly, with transforms of
    // their own
    const StencilChoice sc = choose_stencil(range, 2 * M_PI / wavelength, h, a, lattice_samples, off_lattice, tolerance);
    const double width = sc.stencil.width();
    double outside = 1;
    if (sc.inner > 0) {
        const double sx = std::max(std::fabs(range.ux0), std::fabs(range.ux1)),
                     sy = std::max(std::fabs(range.uy0), std::fabs(range.uy1));
        outside = 1 - std::min(1.0, sc.inner / std::max(sx, 1e-12)) * std::min(1.0, sc.inner / std::max(sy, 1e-12));
    }
    // the rim direct for every point, or the stencil (with the split) where it is cheaper
    const SumGeometry geo = geometry_of(film, wavelength, tolerance, range);
    SummationWork f = cheapest_division(geo, range, n, n, lattice_samples, off_lattice, points, discs_for);
    f.stencil = false;
    if (sc.inner > 0) {
        SummationWork s = cheapest_division(geo, range, n, n, lattice_samples + off_lattice * width, 0.0,
                                            (1 - outside) * points, discs_for);
        s.fast += off_lattice * width * width * kMacCost;
        if (outside > 0) {
            const SummationWork o = cheapest_division(geo, range, n, n, lattice_samples, off_lattice, outside * points,
                                                      discs_for);
            s.fast += o.fast;
            s.nufft_count += o.nufft_count;
        }
        s.stencil = true;
        if (s.fast < f.fast) f = s;
    }
    f.direct = w.direct;
    return f;
}

}  // namespace

const char* summation_name(Summation s) {
    return s == Summation::Direct ? "direct summation" : s == Summation::Nufft ? "NUFFT summation" : "fast summation";
}

Summation default_summation() {
    const char* v = std::getenv("WAVECAM_SUMMATION");
    const std::string name = v ? v : "";
    return name == "direct" ? Summation::Direct : name == "nufft" ? Summation::Nufft : Summation::Fast;
}

bool use_fast(const SummationSettings& s, const SummationWork& w) {
    return s.method == Summation::Nufft || (s.method == Summation::Fast && w.fast < w.direct);
}

namespace {

// Sum 1 through the lattice laid out as L (off-lattice samples the stencil does not take summed
// directly), added to `field`.
bool fast_illuminate(const ApertureSamples& samples, const LatticeLayout& L, const std::vector<PointSource>& sources,
                     double wavelength, int blocks, const SummationSettings& set, PinholeField& field,
                     const ProgressFn& progress) {
    PinholeField off;
    const double share = double(L.off.size()) / std::max<double>(1, samples.size()) * 0.5;
    if (!illuminate_pinhole(L.off, sources, wavelength, off, set.nthreads, progress_part(progress, 0, share)))
        return false;
    std::vector<cdouble> U;
    if (L.nx > 0 &&
        !fast_sources_to_lattice(L, samples, sources, wavelength, blocks, set, U, progress_part(progress, share, 1)))
        return false;
    auto add = [&](size_t j, cdouble u) {
        const cdouble v = u * (double(samples.weight[j]) / wavelength);
        field.re[j] += float(v.real());
        field.im[j] += float(v.imag());
    };
    for (size_t j = 0; j < samples.size(); ++j)
        if (L.cell[j] >= 0) add(j, U[L.cell[j]]);
    for (size_t i = 0; i < L.spread_index.size(); ++i) {
        const double* wx = L.spread_wx.data() + i * L.width;
        const double* wy = L.spread_wy.data() + i * L.width;
        cdouble u = 0;
        for (int b = 0; b < L.width; ++b) {
            const cdouble* row = U.data() + L.spread_cell[i] + long(b) * L.nx;
            cdouble v = 0;
            for (int a = 0; a < L.width; ++a) v += wx[a] * row[a];
            u += wy[b] * v;
        }
        add(L.spread_index[i], u);
    }
    for (size_t i = 0; i < L.off_index.size(); ++i) {
        field.re[L.off_index[i]] += off.re[i];
        field.im[L.off_index[i]] += off.im[i];
    }
    return true;
}

// Sum 2 through the lattice laid out as L, added to `film_field`.
bool fast_film(const ApertureSamples& samples, const LatticeLayout& L, const PinholeField& field,
               const FilmPoints& film, double wavelength, int blocks, const SummationSettings& set,
               cdouble* film_field, const ProgressFn& progress) {
    PinholeField off;
    for (size_t i = 0; i < L.off_index.size(); ++i) {
        off.re.push_back(field.re[L.off_index[i]]);
        off.im.push_back(field.im[L.off_index[i]]);
    }
    const double share = double(L.off.size()) / std::max<double>(1, samples.size()) * 0.5;
    if (!add_film_field(L.off, off, film, wavelength, film_field, set.nthreads, progress_part(progress, 0, share)))
        return false;
    return L.nx == 0 ||
           fast_lattice_to_film(L, samples, field, film, wavelength, blocks, set, film_field, progress_part(progress, share, 1));
}

}  // namespace

bool illuminate_pinhole(const ApertureSamples& samples, const std::vector<PointSource>& sources, double wavelength,
                        PinholeField& field, const SummationSettings& set, const ProgressFn& progress) {
    if (set.method == Summation::Direct || sources.empty() || samples.size() == 0)
        return illuminate_pinhole(samples, sources, wavelength, field, set.nthreads, progress);
    std::vector<Parameter> p;
    for (const PointSource& s : sources) {
        const double R = s.at_infinity ? 1 : std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
        p.push_back({s.x / R, s.y / R, s.at_infinity ? 0.0 : 1.0 / R});
    }
    const DirectionRange range = set.fixed_range ? set.range : range_of(p, 3);
    const double k = 2 * M_PI / wavelength;
    const SampleCount n = count_samples(samples);
    const StencilChoice sc = choose_stencil(range, k, samples.pitch, n.reach, n.on, n.off, set.tolerance);
    // the sources the stencil serves, and the rest
    std::vector<PointSource> inner, outer;
    for (size_t s = 0; s < sources.size(); ++s) (within(sc.inner, p[s][0], p[s][1]) ? inner : outer).push_back(sources[s]);
    const LatticeLayout with = lattice_layout(samples, sc.stencil), without = lattice_layout(samples, no_stencil());
    // the stencil where it serves any source and (deciding here) costs less than direct rim terms
    bool stencil = sc.inner > 0 && !inner.empty() && set.stencil;
    SummationWork w;
    w.blocks = set.blocks;
    if (set.method == Summation::Fast || (set.blocks == 0 && with.nx > 0)) {
        const SummationWork none = work_of(without, samples.pitch, double(sources.size()), range, wavelength, false,
                                           set.tolerance);
        SummationWork split = none;
        if (stencil) {
            split = work_of(with, samples.pitch, double(inner.size()), range, wavelength, false, set.tolerance);
            if (!outer.empty()) {
                const SummationWork o =
                    work_of(without, samples.pitch, double(outer.size()), range, wavelength, false, set.tolerance);
                split.fast += o.fast;
                split.direct += o.direct;
            }
        }
        stencil = stencil && split.fast < none.fast;
        w = stencil ? split : none;
        if (!use_fast(set, w)) return illuminate_pinhole(samples, sources, wavelength, field, set.nthreads, progress);
    }
    field.re.assign(samples.size(), 0.0f);
    field.im.assign(samples.size(), 0.0f);
    if (!stencil) return fast_illuminate(samples, without, sources, wavelength, w.blocks, set, field, progress);
    if (outer.empty()) return fast_illuminate(samples, with, sources, wavelength, w.blocks, set, field, progress);
    const double split = double(inner.size()) / sources.size();
    return fast_illuminate(samples, with, inner, wavelength, w.blocks, set, field, progress_part(progress, 0, split)) &&
           fast_illuminate(samples, without, outer, wavelength, w.blocks, set, field, progress_part(progress, split, 1));
}

bool add_film_field(const ApertureSamples& samples, const PinholeField& field, const FilmPoints& film,
                    double wavelength, std::complex<double>* film_field, const SummationSettings& set,
                    const ProgressFn& progress) {
    if (set.method == Summation::Direct || film.size() == 0 || samples.size() == 0)
        return add_film_field(samples, field, film, wavelength, film_field, set.nthreads, progress);
    DirectionRange range;
    const double f = film.film_distance;
    std::vector<std::array<double, 2>> u(film.size());
    for (size_t t = 0; t < film.size(); ++t) {
        const double R = std::sqrt(double(film.x[t]) * film.x[t] + double(film.y[t]) * film.y[t] + f * f);
        u[t] = {film.x[t] / R, film.y[t] / R};
        range.ux0 = std::min(range.ux0, u[t][0]), range.ux1 = std::max(range.ux1, u[t][0]);
        range.uy0 = std::min(range.uy0, u[t][1]), range.uy1 = std::max(range.uy1, u[t][1]);
    }
    range.rho0 = range.rho1 = 1.0 / f;
    if (set.fixed_range) range = set.range;
    const double k = 2 * M_PI / wavelength;
    const SampleCount n = count_samples(samples);
    const StencilChoice sc = choose_stencil(range, k, samples.pitch, n.reach, n.on, n.off, set.tolerance);
    // the film points the stencil serves, and the rest
    std::vector<size_t> outer;
    for (size_t t = 0; t < film.size(); ++t)
        if (!within(sc.inner, u[t][0], u[t][1])) outer.push_back(t);
    const LatticeLayout with = lattice_layout(samples, sc.stencil), without = lattice_layout(samples, no_stencil());
    // the stencil where it serves any point and (deciding here) costs less than direct rim terms
    bool stencil = sc.inner > 0 && outer.size() < film.size() && set.stencil;
    SummationWork w;
    w.blocks = set.blocks;
    if (set.method == Summation::Fast || (set.blocks == 0 && with.nx > 0)) {
        const SummationWork none = work_of(without, samples.pitch, double(film.size()), range, wavelength, true,
                                           set.tolerance);
        SummationWork split = none;
        if (stencil) {
            split = work_of(with, samples.pitch, double(film.size() - outer.size()), range, wavelength, true,
                            set.tolerance);
            if (!outer.empty()) {
                const SummationWork o =
                    work_of(without, samples.pitch, double(outer.size()), range, wavelength, true, set.tolerance);
                split.fast += o.fast;
                split.direct += o.direct;
            }
        }
        stencil = stencil && split.fast < none.fast;
        w = stencil ? split : none;
        if (!use_fast(set, w))
            return add_film_field(samples, field, film, wavelength, film_field, set.nthreads, progress);
    }
    if (!stencil) return fast_film(samples, without, field, film, wavelength, w.blocks, set, film_field, progress);
    if (outer.empty()) return fast_film(samples, with, field, film, wavelength, w.blocks, set, film_field, progress);
    // two passes over subsets of the points, their results put back in place
    FilmPoints parts[2];
    std::vector<size_t> index[2];
    for (size_t t = 0, o = 0; t < film.size(); ++t) {
        const int which = o < outer.size() && outer[o] == t ? (++o, 1) : 0;
        parts[which].x.push_back(film.x[t]);
        parts[which].y.push_back(film.y[t]);
        index[which].push_back(t);
    }
    const double split = double(parts[0].size()) / film.size();
    for (int which = 0; which < 2; ++which) {
        parts[which].film_distance = f;
        if (parts[which].size() == 0) continue;
        std::vector<cdouble> out(parts[which].size(), 0.0);
        if (!fast_film(samples, which == 0 ? with : without, field, parts[which], wavelength, w.blocks, set, out.data(),
                       progress_part(progress, which == 0 ? 0 : split, which == 0 ? split : 1)))
            return false;
        for (size_t i = 0; i < out.size(); ++i) film_field[index[which][i]] += out[i];
    }
    return true;
}

bool accumulate_film_irradiance(const ApertureSamples& samples, const PinholeField& field, const FilmPoints& film,
                                double wavelength, double scale, float* irradiance, const SummationSettings& set,
                                const ProgressFn& progress) {
    std::vector<cdouble> u(film.size(), 0.0);
    if (!add_film_field(samples, field, film, wavelength, u.data(), set, progress)) return false;
    for (size_t t = 0; t < u.size(); ++t) irradiance[t] += static_cast<float>(scale * std::norm(u[t]));
    return true;
}

}  // namespace wavecam
