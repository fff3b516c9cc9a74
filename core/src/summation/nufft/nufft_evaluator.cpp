// The nufft evaluator (docs/summation.md): both sums through NUFFTs over the pinhole lattice,
// the chirps' remainder interpolated (chirp_interpolation.h). Everything that depends only on the
// plan's geometry is built once, when the plan is committed: the lattice layouts (with and without
// the band-limited stencil), which points the stencil serves, the sub-apertures, the parameter
// boxes, each point's Lagrange weights, each box's skeleton on each sub-aperture and the NUFFTs.
// Each execute computes the points' frequencies and phases per sub-aperture and the transforms.

#include <cmath>

#include "base/parallel.h"
#include "summation/nufft/chirp_interpolation.h"
#include "summation/nufft/lattice_layout.h"
#include "summation/nufft/lattice_nufft.h"
#include "summation/nufft/skeleton_coefficients.h"
#include "summation/nufft/stencil_choice.h"
#include "summation/sum_evaluator.h"

namespace wavecam::detail {
namespace {

using cdouble = std::complex<double>;

// One pass over the lattice for a subset of the points (those the stencil serves, or the rest):
// its layout, and the chirp interpolation built for its points.
struct LatticePass {
    const LatticeLayout* layout = nullptr;
    std::vector<size_t> points;       // the plan's point indices
    std::vector<Parameter> p;         // their parameters
    SubApertures sub;
    std::vector<ChebyshevBox> boxes;
    std::vector<std::vector<size_t>> members;    // per box: indices into `p`
    std::vector<AxisWeights> weights;            // per box
    std::vector<std::vector<NodeSkeleton>> skeletons;  // per sub-aperture, per box
    std::unique_ptr<LatticeNufft> nufft;
    std::vector<PointSource> sources;  // SourcesToPinhole: the pass's sources (for off-lattice direct terms)
    FilmPoints film;                   // PinholeToFilm: the pass's film points
};

// Per point of a pass's parameter box, for one sub-aperture: the NUFFT frequency
// k h (u - grad psi(c)) (radians per lattice step) and the phase exp(i k (psi(c) - grad psi(c).c))
// times the lattice-start phase of the sub-aperture's first cell (i0, j0) and the NUFFT's
// centring, applied once per point.
struct SubApertureFrequencies {
    std::vector<double> fx, fy;
    std::vector<cdouble> shift;
    LatticePoints points() const { return {fx.data(), fy.data(), fx.size()}; }
    SubApertureFrequencies(const LatticePass& pass, size_t box, const ChirpGeometry& geo, const SubAperture& a,
                           double h, int nthreads)
        : fx(pass.members[box].size()), fy(fx.size()), shift(fx.size()) {
        const std::vector<size_t>& in = pass.members[box];
        const std::vector<Parameter>& p = pass.p;
        const LatticeNufft& nufft = *pass.nufft;
        const double k = geo.k;
        parallel_for(0, long(in.size()), thread_count(nthreads), [&](int64_t i) {
            const Parameter& q = p[in[i]];
            const ChirpAtCentre c = geo.at(q, a.cx, a.cy);
            fx[i] = k * h * (q[0] - c.gx);
            fy[i] = k * h * (q[1] - c.gy);
            shift[i] = std::polar(1.0, k * (c.psi - c.gx * a.cx - c.gy * a.cy) - (fx[i] * a.i0 + fy[i] * a.j0) +
                                           nufft.centring_phase(fx[i], fy[i]));
        });
    }
};

class NufftEvaluator final : public SumEvaluator {
public:
    NufftEvaluator(const SumGeometry& g, const SumChoice& choice);
    Result<bool> sources_to_pinhole(const std::vector<cdouble>& weights, PinholeField& field,
                                    const ProgressFn& progress) const override;
    Result<bool> pinhole_to_film(const PinholeField& field, cdouble* film_field,
                                 const ProgressFn& progress) const override;

private:
    void build_pass(LatticePass& pass, const LatticeLayout& layout, const DirectionRange& range);
    // For every sub-aperture and parameter box holding points, in batches of up to kNodeBatch
    // skeleton nodes: `batch_of(part, box, frequencies, j0, batch)` does a batch's transforms.
    // Progress counts the boxes' nodes; false if cancelled.
    template <class Batch>
    bool walk(const LatticePass& pass, const ProgressFn& progress, const Batch& batch_of) const;
    bool pass_to_pinhole(const LatticePass& pass, const std::vector<cdouble>& weights, PinholeField& field,
                         const ProgressFn& progress) const;
    bool pass_to_film(const LatticePass& pass, const PinholeField& field, cdouble* out,
                      const ProgressFn& progress) const;

    SumGeometry g_;
    SumChoice choice_;
    ChirpGeometry geo_;
    double h_ = 0;
    LatticeLayout with_, without_;
    std::vector<LatticePass> passes_;  // one or two; each point in exactly one
};

NufftEvaluator::NufftEvaluator(const SumGeometry& g, const SumChoice& choice) : g_(g), choice_(choice) {
    const ApertureSamples& samples = *g.samples;
    const bool film = g.kind == SumKind::PinholeToFilm;
    h_ = samples.pitch;
    const double k = 2 * M_PI / g.wavelength;
    // every point's parameters: direction components and (sources) inverse distance
    std::vector<Parameter> p;
    if (film) {
        const double f = g.film->film_distance;
        for (size_t t = 0; t < g.film->size(); ++t) {
            const double tx = g.film->x[t], ty = g.film->y[t], R = std::sqrt(tx * tx + ty * ty + f * f);
            p.push_back({tx / R, ty / R, 0.0});
        }
    } else {
        for (const PointSource& s : *g.sources) {
            const double R = s.at_infinity ? 1 : std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
            p.push_back({s.x / R, s.y / R, s.at_infinity ? 0.0 : 1.0 / R});
        }
    }
    DirectionRange range = range_of(p, film ? 2 : 3);
    if (film) range.rho0 = range.rho1 = 1.0 / g.film->film_distance;
    if (g.scope.fixed_range) range = g.scope.range;
    geo_ = {film, film ? g.film->film_distance : 0.0, k, g.settings.tolerance};
    const SampleCount n = count_samples(samples);
    // (none designed where the choice takes none)
    const StencilChoice sc = choice.stencil ? choose_stencil(range, k, h_, n, g.settings.tolerance) : StencilChoice{};
    // the points the stencil serves, and the rest
    std::vector<size_t> inner, outer;
    for (size_t i = 0; i < p.size(); ++i) (within(sc.inner, p[i][0], p[i][1]) ? inner : outer).push_back(i);
    const bool stencil = choice.stencil && sc.inner > 0 && !inner.empty();
    without_ = lattice_layout(samples, StencilChoice::no_stencil());
    if (stencil) with_ = lattice_layout(samples, sc.stencil);
    auto add_pass = [&](const LatticeLayout& layout, std::vector<size_t> points) {
        if (points.empty()) return;
        LatticePass& pass = passes_.emplace_back();
        pass.points = std::move(points);
        for (size_t i : pass.points) {
            pass.p.push_back(p[i]);
            if (film) {
                pass.film.x.push_back(g.film->x[i]);
                pass.film.y.push_back(g.film->y[i]);
            } else {
                pass.sources.push_back((*g.sources)[i]);
            }
        }
        pass.film.film_distance = film ? g.film->film_distance : 0.0;
        build_pass(pass, layout, range);
    };
    if (!stencil) {
        std::vector<size_t> all(p.size());
        for (size_t i = 0; i < all.size(); ++i) all[i] = i;
        add_pass(without_, std::move(all));
    } else {
        add_pass(with_, std::move(inner));
        add_pass(without_, std::move(outer));
    }
}

void NufftEvaluator::build_pass(LatticePass& pass, const LatticeLayout& layout, const DirectionRange& range) {
    pass.layout = &layout;
    if (layout.nx == 0) return;
    const int nthreads = g_.settings.nthreads;
    pass.sub = split_lattice(layout, choice_.blocks, h_);
    pass.boxes = geo_.tiling(g_.scope.fixed_range ? range : range_of(pass.p, geo_.dims()), discs_of(pass.sub));
    pass.members = group(pass.boxes, pass.p);
    for (size_t bi = 0; bi < pass.boxes.size(); ++bi) pass.weights.emplace_back(pass.boxes[bi], pass.p, pass.members[bi], nthreads);
    pass.nufft = std::make_unique<LatticeNufft>(pass.sub.bnx, pass.sub.bny, g_.settings.tolerance, nthreads);
    for (const SubAperture& part : pass.sub.parts) {
        std::vector<NodeSkeleton>& sk = pass.skeletons.emplace_back();
        for (size_t bi = 0; bi < pass.boxes.size(); ++bi)
            sk.push_back(pass.members[bi].empty() ? NodeSkeleton{}
                                                  : box_skeleton(geo_, pass.boxes[bi], {part.cx, part.cy, part.reach}));
    }
}

template <class Batch>
bool NufftEvaluator::walk(const LatticePass& pass, const ProgressFn& progress, const Batch& batch_of) const {
    double total = 0, done = 0;
    for (const ChebyshevBox& bx : pass.boxes) total += double(bx.rank()) * pass.sub.parts.size();
    for (size_t pi = 0; pi < pass.sub.parts.size(); ++pi) {
        const SubAperture& part = pass.sub.parts[pi];
        for (size_t bi = 0; bi < pass.boxes.size(); ++bi) {
            const ChebyshevBox& bx = pass.boxes[bi];
            const NodeSkeleton& sk = pass.skeletons[pi][bi];
            const int r = sk.rank();
            if (r == 0) {
                done += bx.rank();
                continue;
            }
            const SubApertureFrequencies fr(pass, bi, geo_, part, h_, g_.settings.nthreads);
            for (int j0 = 0; j0 < r; j0 += kNodeBatch) {
                const int batch = std::min(kNodeBatch, r - j0);
                batch_of(part, bi, fr, j0, batch);
                done += double(bx.rank()) * batch / r;
                if (progress && !progress(done / total)) return false;
            }
        }
    }
    return true;
}

// Sum 1 over the pass's lattice: U at every lattice cell, then each sample's field (on the
// lattice, read through the stencil, or summed directly off it), added to `field`.
bool NufftEvaluator::pass_to_pinhole(const LatticePass& pass, const std::vector<cdouble>& weights, PinholeField& field,
                                     const ProgressFn& progress) const {
    const ApertureSamples& samples = *g_.samples;
    const LatticeLayout& L = *pass.layout;
    const double wavelength = g_.wavelength;
    const int nthreads = g_.settings.nthreads;
    std::vector<cdouble> w(pass.points.size());
    for (size_t i = 0; i < w.size(); ++i) w[i] = weights[pass.points[i]];
    PinholeField off;
    const double share = double(L.off.size()) / std::max<double>(1, samples.size()) * 0.5;
    if (!illuminate_pinhole(L.off, weighted(pass.sources, w), wavelength, off, nthreads, progress_slice(progress, 0, share)))
        return false;
    std::vector<cdouble> U(size_t(L.nx) * L.ny, 0.0);
    if (L.nx > 0) {
        // each source's strength over its distance (plane waves: as it is)
        std::vector<cdouble> b(w.size());
        for (size_t i = 0; i < w.size(); ++i) b[i] = pass.p[i][2] > 0 ? w[i] * pass.p[i][2] : w[i];
        const SubApertures& S = pass.sub;
        const size_t cells = size_t(S.bnx) * S.bny;
        std::vector<std::vector<cfloat>> lattice(kNodeBatch, std::vector<cfloat>(cells));
        std::vector<cfloat*> out(kNodeBatch);
        for (int q = 0; q < kNodeBatch; ++q) out[q] = lattice[q].data();
        std::vector<cdouble> base;
        std::vector<cfloat> a;
        const bool done = walk(pass, progress_slice(progress, share, 1),
                               [&](const SubAperture& part, size_t bi, const SubApertureFrequencies& fr, int j0, int batch) {
            const std::vector<size_t>& in = pass.members[bi];
            const ChebyshevBox& bx = pass.boxes[bi];
            const NodeSkeleton& sk = pass.skeletons[&part - S.parts.data()][bi];
            if (j0 == 0) {
                base.resize(in.size());
                for (size_t i = 0; i < in.size(); ++i) base[i] = b[in[i]] * fr.shift[i];
            }
            skeleton_coefficients({pass.weights[bi], 3, in.size(), bx.rank()}, {sk, j0, batch}, base.data(), a, nthreads);
            pass.nufft->to_lattice(fr.points(), a.data(), batch, out.data());
            for (int q = 0; q < batch; ++q) {
                const ChirpAtCentre node = geo_.at(bx.node(sk.rows[j0 + q]), part.cx, part.cy);
                const cfloat* F = lattice[q].data();
                parallel_for(0, long(cells), thread_count(nthreads), [&](int64_t c) {
                    if (part.cells[c] >= 0)
                        U[part.cells[c]] +=
                            cdouble(node.remainder(cell_x(part, S, c, h_), cell_y(part, S, c, h_), 1 / wavelength, 1) * F[c]);
                });
            }
        });
        if (!done) return false;
    }
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

// Sum 2 from the samples' field to the pass's film points, added to out[i] (pass-local).
bool NufftEvaluator::pass_to_film(const LatticePass& pass, const PinholeField& field, cdouble* out,
                                  const ProgressFn& progress) const {
    const ApertureSamples& samples = *g_.samples;
    const LatticeLayout& L = *pass.layout;
    const double wavelength = g_.wavelength, f = pass.film.film_distance;
    const int nthreads = g_.settings.nthreads;
    PinholeField off;
    for (size_t i = 0; i < L.off_index.size(); ++i) {
        off.re.push_back(field.re[L.off_index[i]]);
        off.im.push_back(field.im[L.off_index[i]]);
    }
    const double share = double(L.off.size()) / std::max<double>(1, samples.size()) * 0.5;
    if (!add_film_field({L.off, off, pass.film, wavelength}, out, nthreads, progress_slice(progress, 0, share)))
        return false;
    if (L.nx == 0) return true;
    std::vector<cfloat> w(size_t(L.nx) * L.ny, cfloat(0));
    for (size_t j = 0; j < samples.size(); ++j)
        if (L.cell[j] >= 0) w[L.cell[j]] = cfloat(field.re[j], field.im[j]);
    // the stencil's samples spread onto the cells around them
    for (size_t i = 0; i < L.spread_index.size(); ++i) {
        const size_t j = L.spread_index[i];
        const cdouble v(field.re[j], field.im[j]);
        for (int b = 0; b < L.width; ++b)
            for (int a = 0; a < L.width; ++a)
                w[L.spread_cell[i] + long(b) * L.nx + a] +=
                    cfloat(v * (L.spread_wx[i * L.width + a] * L.spread_wy[i * L.width + b]));
    }
    const SubApertures& S = pass.sub;
    const size_t cells = size_t(S.bnx) * S.bny;
    std::vector<std::vector<cfloat>> g(kNodeBatch, std::vector<cfloat>(cells));
    std::vector<const cfloat*> lattices(kNodeBatch);
    for (int q = 0; q < kNodeBatch; ++q) lattices[q] = g[q].data();
    std::vector<cfloat> G, coeff;
    return walk(pass, progress_slice(progress, share, 1),
                [&](const SubAperture& part, size_t bi, const SubApertureFrequencies& fr, int j0, int batch) {
        const std::vector<size_t>& in = pass.members[bi];
        const ChebyshevBox& bx = pass.boxes[bi];
        const NodeSkeleton& sk = pass.skeletons[&part - S.parts.data()][bi];
        for (int q = 0; q < batch; ++q) {
            const ChirpAtCentre node = geo_.at(bx.node(sk.rows[j0 + q]), part.cx, part.cy);
            cfloat* gq = g[q].data();
            parallel_for(0, long(cells), thread_count(nthreads), [&](int64_t c) {
                gq[c] = part.cells[c] >= 0
                            ? w[part.cells[c]] * node.remainder(cell_x(part, S, c, h_), cell_y(part, S, c, h_), 1 / wavelength, 2)
                            : cfloat(0);
            });
        }
        skeleton_coefficients({pass.weights[bi], 2, in.size(), bx.rank()}, {sk, j0, batch}, nullptr, coeff, nthreads);
        G.resize(in.size());
        pass.nufft->from_lattice(lattices.data(), batch, fr.points(), coeff.data(), G.data());
        parallel_for(0, long(in.size()), thread_count(nthreads), [&](int64_t i) {
            const double tx = pass.film.x[in[i]], ty = pass.film.y[in[i]];
            out[in[i]] += f / (tx * tx + ty * ty + f * f) * fr.shift[i] * cdouble(G[i]);  // f / R_t^2
        });
    });
}

Result<bool> NufftEvaluator::sources_to_pinhole(const std::vector<cdouble>& weights, PinholeField& field,
                                                const ProgressFn& progress) const {
    field.re.assign(g_.samples->size(), 0.0f);
    field.im.assign(g_.samples->size(), 0.0f);
    const double total = double(g_.sources->size());
    double at = 0;
    for (const LatticePass& pass : passes_) {
        const double next = at + pass.points.size() / total;
        if (!pass_to_pinhole(pass, weights, field, progress_slice(progress, at, next))) return finished(false);
        at = next;
    }
    return finished(true);
}

Result<bool> NufftEvaluator::pinhole_to_film(const PinholeField& field, cdouble* film_field,
                                             const ProgressFn& progress) const {
    const double total = double(g_.film->size());
    double at = 0;
    for (const LatticePass& pass : passes_) {
        const double next = at + pass.points.size() / total;
        const ProgressFn part = progress_slice(progress, at, next);
        if (passes_.size() == 1) {
            if (!pass_to_film(pass, field, film_field, part)) return finished(false);
        } else {
            std::vector<cdouble> out(pass.points.size(), 0.0);
            if (!pass_to_film(pass, field, out.data(), part)) return finished(false);
            for (size_t i = 0; i < out.size(); ++i) film_field[pass.points[i]] += out[i];
        }
        at = next;
    }
    return finished(true);
}

}  // namespace

std::unique_ptr<SumEvaluator> make_nufft_evaluator(const SumGeometry& g, const SumChoice& choice) {
    return std::make_unique<NufftEvaluator>(g, choice);
}

}  // namespace wavecam::detail
