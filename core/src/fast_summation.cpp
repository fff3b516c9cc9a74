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
#include <cstdlib>
#include <string>
#include <cmath>

#include "chebyshev_box.h"
#include "lattice_nufft.h"

namespace wavecam {
namespace {

using detail::cfloat;
using detail::ChebyshevBox;
using detail::Parameter;
using cdouble = std::complex<double>;

// The chirp exp(i k psi) / g^power for direction (ux, uy), inverse distance rho, at (x, y).
inline cdouble chirp(double ux, double uy, double rho, double x, double y, double k, int power) {
    const double q2 = x * x + y * y, p = ux * x + uy * y;
    const double g = std::sqrt(std::max(1e-300, 1.0 - 2.0 * rho * p + rho * rho * q2));
    const double psi = rho * (q2 + p * (rho * q2 - 2.0 * p) / (1.0 + g)) / (1.0 + g);
    return std::polar(power == 1 ? 1.0 / g : 1.0 / (g * g), k * psi);
}

// The pinhole samples split into the lattice box they sit on (cell centres m h, n h) and the
// rest (rim centroids, grey or holed apertures), summed directly.
struct LatticeLayout {
    long i0 = 0, j0 = 0;
    int nx = 0, ny = 0;
    std::vector<long> cell;          // per sample: (n - j0) * nx + (m - i0), or -1 off the lattice
    std::vector<char> used;          // per lattice cell: a sample sits there
    ApertureSamples off;             // off-lattice samples
    std::vector<size_t> off_index;   // their indices in the samples
    size_t on = 0;                   // lattice samples
    // Radius of the disc holding the lattice box (pitch h), with a cell to spare: the probes' reach.
    double radius(double h) const { return std::sqrt(0.5) * h * std::max(nx, ny) + h; }
};

LatticeLayout lattice_layout(const ApertureSamples& s) {
    LatticeLayout L;
    const double h = s.pitch;
    L.off.pitch = h;
    std::vector<long> im(s.size()), jm(s.size());
    long i0 = 0, i1 = -1, j0 = 0, j1 = -1;
    bool any = false;
    for (size_t k = 0; k < s.size(); ++k) {
        const double fx = s.x[k] / h, fy = s.y[k] / h;
        const long i = std::lround(fx), j = std::lround(fy);
        // a float position within 1e-4 pitch of a cell centre is that cell's centre
        if (std::abs(fx - i) < 1e-4 && std::abs(fy - j) < 1e-4) {
            im[k] = i;
            jm[k] = j;
            if (!any) i0 = i1 = i, j0 = j1 = j, any = true;
            i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
        } else {
            im[k] = LONG_MIN;
        }
    }
    L.i0 = i0, L.j0 = j0;
    L.nx = any ? int(i1 - i0 + 1) : 0;
    L.ny = any ? int(j1 - j0 + 1) : 0;
    L.cell.assign(s.size(), -1);
    L.used.assign(size_t(L.nx) * L.ny, 0);
    for (size_t k = 0; k < s.size(); ++k) {
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

// Probe points for choosing interpolation nodes: the rim of the aperture's bounding disc (where
// the chirp varies fastest) in 8 directions, and half way in 4.
std::vector<std::array<double, 2>> probes(double radius) {
    std::vector<std::array<double, 2>> p;
    for (int a = 0; a < 8; ++a) p.push_back({radius * std::cos(a * M_PI / 4), radius * std::sin(a * M_PI / 4)});
    for (int a = 0; a < 4; ++a)
        p.push_back({0.5 * radius * std::cos(M_PI / 4 + a * M_PI / 2), 0.5 * radius * std::sin(M_PI / 4 + a * M_PI / 2)});
    return p;
}

double film_rho(double nx, double ny, double f) { return std::sqrt(std::max(0.0, 1.0 - nx * nx - ny * ny)) / f; }

// The boxes of one sum: sources (3 parameters ux, uy, rho; chirp / g) or film points (2: nx, ny;
// rho from the film distance; chirp / g^2).
struct SumGeometry {
    bool film = false;
    double f = 0, k = 0, radius = 0, tolerance = kSummationTolerance;
    ChebyshevBox box(const DirectionRange& r) const {
        ChebyshevBox b;
        b.dims = film ? 2 : 3;
        b.lo = {r.ux0, r.uy0, r.rho0};
        b.hi = {r.ux1, r.uy1, r.rho1};
        return b;
    }
    cdouble kernel(const Parameter& p, double x, double y) const {
        return film ? chirp(p[0], p[1], film_rho(p[0], p[1], f), x, y, k, 2) : chirp(p[0], p[1], p[2], x, y, k, 1);
    }
    std::vector<ChebyshevBox> plan(const DirectionRange& r) const {
        const auto pr = probes(radius);
        return detail::plan_boxes(
            box(r), [&](const Parameter& p, int i) { return kernel(p, pr[i][0], pr[i][1]); }, int(pr.size()),
            tolerance, kMaxRank);
    }
    static constexpr int kMaxRank = 1000;  // split only where an axis needs more than 10 nodes
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
        std::vector<double> full(b.rank());
        for (size_t i = 0; i < points.size(); ++i) {
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

// The NUFFT frequencies of the points `in` (radians per lattice step, k h u) and each point's
// phase for the lattice box starting at cell (i0, j0), exp(-i k u.xi) = exp(-i (fx (i0 + m) +
// fy (j0 + n))), with the NUFFT's centring: the factor both sums apply once per point.
struct BoxFrequencies {
    std::vector<double> fx, fy;
    std::vector<cdouble> shift;
    BoxFrequencies(const std::vector<size_t>& in, const std::vector<Parameter>& p, double kh, const LatticeLayout& L,
                   const detail::LatticeNufft& nufft)
        : fx(in.size()), fy(in.size()), shift(in.size()) {
        for (size_t i = 0; i < in.size(); ++i) {
            fx[i] = kh * p[in[i]][0];
            fy[i] = kh * p[in[i]][1];
            shift[i] = std::polar(1.0, -(fx[i] * L.i0 + fy[i] * L.j0)) * nufft.centring(fx[i], fy[i]);
        }
    }
};

// Transforms run in batches of up to this many interpolation nodes: a point's kernel weights are
// computed once per batch, at the memory of this many grids.
constexpr int kBatch = 8;

// Fast sum 1 over the lattice samples: U at every lattice cell (0 elsewhere).
bool fast_sources_to_lattice(const LatticeLayout& L, const ApertureSamples& samples,
                             const std::vector<PointSource>& sources, double wavelength,
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
    SumGeometry geo{false, 0, k, L.radius(h), set.tolerance};
    const std::vector<ChebyshevBox> boxes = geo.plan(set.fixed_range ? set.range : range_of(p, 3));
    const auto members = group(boxes, p);
    detail::LatticeNufft nufft(L.nx, L.ny, set.tolerance, set.nthreads);
    U.assign(size_t(L.nx) * L.ny, 0.0);
    std::vector<std::vector<cfloat>> lattice(kBatch, std::vector<cfloat>(U.size()));
    std::vector<cfloat*> out(kBatch);
    for (int q = 0; q < kBatch; ++q) out[q] = lattice[q].data();
    double total = 0, done = 0;
    for (const ChebyshevBox& bx : boxes) total += bx.rank();
    for (size_t bi = 0; bi < boxes.size(); ++bi) {
        const ChebyshevBox& bx = boxes[bi];
        const std::vector<size_t>& in = members[bi];
        if (in.empty()) {
            done += bx.rank();
            continue;
        }
        const AxisWeights aw(bx, p, in);
        const BoxFrequencies fr(in, p, k * h, L, nufft);
        std::vector<cdouble> base(in.size());
        for (size_t i = 0; i < in.size(); ++i) base[i] = b[in[i]] * fr.shift[i];
        for (int q0 = 0; q0 < bx.rank(); q0 += kBatch) {
            const int batch = std::min(kBatch, bx.rank() - q0);
            std::vector<cfloat> a(in.size() * batch);
            for (size_t i = 0; i < in.size(); ++i)
                for (int q = 0; q < batch; ++q) a[i * batch + q] = cfloat(base[i] * aw.at(i, q0 + q, 3));
            nufft.to_lattice(fr.fx.data(), fr.fy.data(), a.data(), batch, in.size(), out.data());
            for (int q = 0; q < batch; ++q) {
                const Parameter node = bx.node(q0 + q);
                const cfloat* F = lattice[q].data();
#pragma omp parallel for schedule(static) num_threads(threads(set.nthreads))
                for (long c = 0; c < long(U.size()); ++c)
                    if (L.used[c]) U[c] += geo.kernel(node, (L.i0 + c % L.nx) * h, (L.j0 + c / L.nx) * h) * cdouble(F[c]);
            }
            done += batch;
            if (progress && !progress(done / total)) return false;
        }
    }
    return true;
}

// Fast sum 2 from the lattice samples' field to every film point, added to `out`.
bool fast_lattice_to_film(const LatticeLayout& L, const ApertureSamples& samples, const PinholeField& field,
                          const FilmPoints& film, double wavelength, const SummationSettings& set, cdouble* out,
                          const ProgressFn& progress) {
    const double k = 2 * M_PI / wavelength, h = samples.pitch, f = film.film_distance;
    std::vector<Parameter> p(film.size());
    for (size_t t = 0; t < film.size(); ++t) {
        const double tx = film.x[t], ty = film.y[t], R = std::sqrt(tx * tx + ty * ty + f * f);
        p[t] = {tx / R, ty / R, 0.0};
    }
    std::vector<cfloat> w(size_t(L.nx) * L.ny, cfloat(0));
    for (size_t j = 0; j < samples.size(); ++j)
        if (L.cell[j] >= 0) w[L.cell[j]] = cfloat(field.re[j], field.im[j]);
    SumGeometry geo{true, f, k, L.radius(h), set.tolerance};
    const std::vector<ChebyshevBox> boxes = geo.plan(set.fixed_range ? set.range : range_of(p, 2));
    const auto members = group(boxes, p);
    detail::LatticeNufft nufft(L.nx, L.ny, set.tolerance, set.nthreads);
    std::vector<std::vector<cfloat>> g(kBatch, std::vector<cfloat>(w.size()));
    std::vector<const cfloat*> lattices(kBatch);
    for (int q = 0; q < kBatch; ++q) lattices[q] = g[q].data();
    double total = 0, done = 0;
    for (const ChebyshevBox& bx : boxes) total += bx.rank();
    for (size_t bi = 0; bi < boxes.size(); ++bi) {
        const ChebyshevBox& bx = boxes[bi];
        const std::vector<size_t>& in = members[bi];
        if (in.empty()) {
            done += bx.rank();
            continue;
        }
        const AxisWeights aw(bx, p, in);
        const BoxFrequencies fr(in, p, k * h, L, nufft);
        std::vector<cdouble> base(in.size());
        for (size_t i = 0; i < in.size(); ++i) {
            const double tx = film.x[in[i]], ty = film.y[in[i]];
            base[i] = f / (tx * tx + ty * ty + f * f) * fr.shift[i];  // f / R_t^2
        }
        std::vector<cfloat> G(in.size());
        for (int q0 = 0; q0 < bx.rank(); q0 += kBatch) {
            const int batch = std::min(kBatch, bx.rank() - q0);
            for (int q = 0; q < batch; ++q) {
                const Parameter node = bx.node(q0 + q);
                cfloat* gq = g[q].data();
#pragma omp parallel for schedule(static) num_threads(threads(set.nthreads))
                for (long c = 0; c < long(w.size()); ++c)
                    gq[c] = L.used[c] ? w[c] * cfloat(geo.kernel(node, (L.i0 + c % L.nx) * h, (L.j0 + c / L.nx) * h))
                                      : cfloat(0);
            }
            std::vector<float> coeff(in.size() * batch);
            for (size_t i = 0; i < in.size(); ++i)
                for (int q = 0; q < batch; ++q) coeff[i * batch + q] = float(aw.at(i, q0 + q, 2));
            nufft.from_lattice(lattices.data(), batch, fr.fx.data(), fr.fy.data(), coeff.data(), in.size(), G.data());
            for (size_t i = 0; i < in.size(); ++i) out[in[i]] += base[i] * cdouble(G[i]);
            done += batch;
            if (progress && !progress(done / total)) return false;
        }
    }
    return true;
}

SummationWork work_of(const LatticeLayout& L, double points, const DirectionRange& r, double radius,
                      double wavelength, bool film, double tolerance) {
    return summation_work(double(L.on), std::max(L.nx, L.ny), double(L.off.size()), points, r, radius, wavelength,
                          film, tolerance);
}

}  // namespace

SummationWork summation_work(double lattice_samples, int samples_across, double off_lattice, double points,
                             const DirectionRange& range, double aperture_radius, double wavelength, bool film,
                             double tolerance) {
    SummationWork w;
    w.direct = (lattice_samples + off_lattice) * points;
    if (lattice_samples <= 0) {
        w.fast = w.direct;
        return w;
    }
    SumGeometry geo{film, 0, 2 * M_PI / wavelength, aperture_radius, tolerance};
    if (film) geo.f = 1.0 / std::max(range.rho1, 1e-9);  // the film's distance: 1/R on axis
    const std::vector<ChebyshevBox> boxes = geo.plan(range);
    const detail::LatticeNufft nufft(samples_across, samples_across, tolerance, 1);
    // each point meets one box: its rank in kernel taps; each node an FFT and a lattice of chirps
    double ranks = 0, point_rank = 0, volume = 0;
    for (const ChebyshevBox& b : boxes) {
        double v = 1;
        for (int d = 0; d < b.dims; ++d) v *= std::max(b.hi[d] - b.lo[d], 1e-12);
        volume += v;
        point_rank += v * b.rank();
        ranks += b.rank();
    }
    w.nufft_count = int(ranks);
    w.fast = ranks * (kFftCost * nufft.fft_work() + kChirpCost * lattice_samples) +
             (point_rank / volume) * points * kTapCost * nufft.taps_per_point() + off_lattice * points;
    return w;
}

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

bool illuminate_pinhole(const ApertureSamples& samples, const std::vector<PointSource>& sources, double wavelength,
                        PinholeField& field, const SummationSettings& set, const ProgressFn& progress) {
    if (set.method == Summation::Direct || sources.empty() || samples.size() == 0)
        return illuminate_pinhole(samples, sources, wavelength, field, set.nthreads, progress);
    const LatticeLayout L = lattice_layout(samples);
    if (set.method == Summation::Fast) {
        std::vector<Parameter> p;
        for (const PointSource& s : sources) {
            const double R = s.at_infinity ? 1 : std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
            p.push_back({s.x / R, s.y / R, s.at_infinity ? 0.0 : 1.0 / R});
        }
        const SummationWork w = work_of(L, double(sources.size()), range_of(p, 3),
                                        std::sqrt(0.5) * samples.pitch * std::max(L.nx, L.ny), wavelength, false,
                                        set.tolerance);
        if (!use_fast(set, w)) return illuminate_pinhole(samples, sources, wavelength, field, set.nthreads, progress);
    }
    // the direct part first (off-lattice samples), then the lattice's NUFFTs
    PinholeField off;
    const double share = double(L.off.size()) / std::max<double>(1, samples.size()) * 0.5;
    if (!illuminate_pinhole(L.off, sources, wavelength, off, set.nthreads, progress_part(progress, 0, share)))
        return false;
    std::vector<cdouble> U;
    if (L.on > 0 &&
        !fast_sources_to_lattice(L, samples, sources, wavelength, set, U, progress_part(progress, share, 1)))
        return false;
    field.re.assign(samples.size(), 0.0f);
    field.im.assign(samples.size(), 0.0f);
    for (size_t j = 0; j < samples.size(); ++j) {
        if (L.cell[j] < 0) continue;
        const cdouble v = U[L.cell[j]] * (double(samples.weight[j]) / wavelength);
        field.re[j] = float(v.real());
        field.im[j] = float(v.imag());
    }
    for (size_t i = 0; i < L.off_index.size(); ++i) {
        field.re[L.off_index[i]] = off.re[i];
        field.im[L.off_index[i]] = off.im[i];
    }
    return true;
}

bool add_film_field(const ApertureSamples& samples, const PinholeField& field, const FilmPoints& film,
                    double wavelength, std::complex<double>* film_field, const SummationSettings& set,
                    const ProgressFn& progress) {
    if (set.method == Summation::Direct || film.size() == 0 || samples.size() == 0)
        return add_film_field(samples, field, film, wavelength, film_field, set.nthreads, progress);
    const LatticeLayout L = lattice_layout(samples);
    if (set.method == Summation::Fast) {
        DirectionRange r;
        const double f = film.film_distance;
        for (size_t t = 0; t < film.size(); ++t) {
            const double R = std::sqrt(double(film.x[t]) * film.x[t] + double(film.y[t]) * film.y[t] + f * f);
            r.ux0 = std::min(r.ux0, film.x[t] / R), r.ux1 = std::max(r.ux1, film.x[t] / R);
            r.uy0 = std::min(r.uy0, film.y[t] / R), r.uy1 = std::max(r.uy1, film.y[t] / R);
        }
        r.rho0 = r.rho1 = 1.0 / f;
        const SummationWork w = work_of(L, double(film.size()), r, std::sqrt(0.5) * samples.pitch * std::max(L.nx, L.ny),
                                        wavelength, true, set.tolerance);
        if (!use_fast(set, w))
            return add_film_field(samples, field, film, wavelength, film_field, set.nthreads, progress);
    }
    PinholeField off;
    for (size_t i = 0; i < L.off_index.size(); ++i) {
        off.re.push_back(field.re[L.off_index[i]]);
        off.im.push_back(field.im[L.off_index[i]]);
    }
    const double share = double(L.off.size()) / std::max<double>(1, samples.size()) * 0.5;
    if (!add_film_field(L.off, off, film, wavelength, film_field, set.nthreads, progress_part(progress, 0, share)))
        return false;
    return L.on == 0 ||
           fast_lattice_to_film(L, samples, field, film, wavelength, set, film_field, progress_part(progress, share, 1));
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
