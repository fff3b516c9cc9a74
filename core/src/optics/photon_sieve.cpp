#include "wavecam/photon_sieve.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "base/counter_random.h"

namespace wavecam {
namespace {

// Uniform in [0, 1) from the seed, the zone and an index: a counter-based hash (SplitMix64,
// counter_random.h), so hole j of zone n gets the same random number on every machine without
// storing the holes.
double uniform(uint32_t seed, int zone, uint64_t index) {
    using detail::splitmix64;
    return double(splitmix64(splitmix64(splitmix64(seed) + uint64_t(zone)) + index) >> 11) * 0x1.0p-53;
}

// r_n = sqrt(n / N) in units of R.
double zone_radius(int n, int zones) { return std::sqrt(double(n) / zones); }

// Zone index n (1-based) of radius rho (units of R): r_(n-1) <= rho < r_n.
long zone_of(double rho, int zones) { return long(std::floor(zones * rho * rho)) + 1; }

// Calls visit(x, y, radius) for the central disc and every hole that may touch the disc of
// radius `reach` around (x, y) (metres); in-sector placement bounds each hole's angle.
template <class Visit>
void nearby_holes(const SieveDesign& d, double R, double x, double y, double reach, Visit visit) {
    const double rho = std::hypot(x, y), near = std::max(0.0, rho - reach) / R, far = (rho + reach) / R;
    const double r1 = sieve_centre_radius(d);
    if (near < r1) visit(0.0, 0.0, r1 * R);
    // A hole of zone n spans zones n-2..n+2 at most (check_sieve keeps rings apart).
    long lo = std::max(3L, zone_of(near, d.zones) - 2), hi = std::min(long(d.zones), zone_of(far, d.zones) + 2);
    if (lo % 2 == 0) ++lo;
    const double theta = std::atan2(y, x);
    const double spread = reach < rho ? std::asin(reach / rho) : M_PI;  // half-angle the disc subtends
    for (long n = lo; n <= hi; n += 2) {
        const SieveRing ring = sieve_ring(d, int(n));
        const double sector = 2 * M_PI / ring.holes;
        long j0 = long(std::floor((theta - spread - ring.rotation) / sector));
        long j1 = long(std::floor((theta + spread - ring.rotation) / sector));
        if (j1 - j0 + 1 >= ring.holes) {
            j0 = 0;
            j1 = ring.holes - 1;
        }
        for (long j = j0; j <= j1; ++j) {
            const long k = ((j % ring.holes) + ring.holes) % ring.holes;
            const double a = sieve_hole_angle(d, ring, k);
            visit(R * ring.radius * std::cos(a), R * ring.radius * std::sin(a), R * ring.hole_radius);
        }
    }
}

}  // namespace

double sieve_centre_radius(const SieveDesign& d) { return zone_radius(1, d.zones); }

SieveRing sieve_ring(const SieveDesign& d, int zone) {
    SieveRing r;
    r.zone = zone;
    r.radius = std::sqrt((zone - 0.5) / d.zones);  // the zone's mean phase
    r.hole_radius = 0.5 * d.hole_ratio * (zone_radius(zone, d.zones) - zone_radius(zone - 1, d.zones));
    r.holes = long(std::floor(d.fill * 2 * M_PI * r.radius / (2 * r.hole_radius)));
    r.rotation = 2 * M_PI * uniform(d.seed, zone, ~uint64_t(0));
    r.margin = std::asin(std::min(1.0, r.hole_radius / r.radius));
    return r;
}

std::vector<SieveRing> sieve_rings(const SieveDesign& d) {
    std::vector<SieveRing> rings;
    for (int n = 3; n <= d.zones; n += 2) rings.push_back(sieve_ring(d, n));
    return rings;
}

double sieve_hole_angle(const SieveDesign& d, const SieveRing& ring, long j) {
    const double sector = 2 * M_PI / ring.holes;
    return ring.rotation + sector * j + ring.margin + uniform(d.seed, ring.zone, uint64_t(j)) * (sector - 2 * ring.margin);
}

double sieve_max_hole_ratio(int zones) {
    // Rings n and n+2 touch when K (w_n + w_(n+2)) / 2 = rho_(n+2) - rho_n; ring 3 touches the
    // central disc when K w_3 / 2 = rho_3 - r_1.
    const SieveDesign unit{zones, 1.0};
    double best = INFINITY;
    double inner_edge = sieve_centre_radius(unit), inner_width = 0;  // previous ring: centre, width (K = 1 radii)
    for (int n = 3; n <= zones; n += 2) {
        const SieveRing r = sieve_ring(unit, n);
        best = std::min(best, (r.radius - inner_edge) / (r.hole_radius + inner_width));
        inner_edge = r.radius;
        inner_width = r.hole_radius;
    }
    return best;
}

Result<bool> check_sieve(const SieveDesign& d, const std::string& field) {
    auto fail = [&](const std::string& m) { return Result<bool>::failure(field + ": " + m); };
    if (d.zones < 3)
        return fail("a photon sieve needs N >= 3 zones (its holes sit on the open zones 3, 5, ...; zone 1 is the "
                    "central disc), got N = " + std::to_string(d.zones));
    const double kmax = sieve_max_hole_ratio(d.zones);
    if (!(d.hole_ratio > 0 && d.hole_ratio <= kmax)) {
        std::ostringstream m;
        m << "hole diameter " << d.hole_ratio << "x the zone width: expected more than 0x and at most " << kmax
          << "x for " << d.zones << " zones (wider holes of neighbouring open zones overlap; 1.5x is the optimum)";
        return fail(m.str());
    }
    if (!(d.fill > 0 && d.fill <= 0.9)) {
        std::ostringstream m;
        m << "fill " << d.fill * 100 << "%: expected more than 0% and at most 90% of each ring's circumference "
          << "(holes placed at random in azimuth need room)";
        return fail(m.str());
    }
    for (const SieveRing& r : sieve_rings(d)) {
        if (r.holes < 1) {
            std::ostringstream m;
            m << "fill " << d.fill * 100 << "% leaves zone " << r.zone << " without a hole; expected a fill of at least "
              << std::ceil(100 * 2 * r.hole_radius / (2 * M_PI * r.radius) * 10) / 10 << "%";
            return fail(m.str());
        }
        if (2 * r.margin > 2 * M_PI / r.holes)
            return fail("zone " + std::to_string(r.zone) + " has no room for its holes; expected a smaller fill");
    }
    return Result<bool>::success(true);
}

std::vector<SieveHole> sieve_holes(const SieveDesign& d, double R) {
    std::vector<SieveHole> holes{{0.0, 0.0, R * sieve_centre_radius(d)}};
    for (const SieveRing& r : sieve_rings(d))
        for (long j = 0; j < r.holes; ++j) {
            const double a = sieve_hole_angle(d, r, j);
            holes.push_back({R * r.radius * std::cos(a), R * r.radius * std::sin(a), R * r.hole_radius});
        }
    return holes;
}

DiscMoments disc_in_cell(double cx, double cy, double a, const ApertureCell& cell) {
    const double x0 = cell.x0, x1 = cell.x1, y0 = cell.y0, y1 = cell.y1;
    // With u = x - cx, v = y - cy, s(u) = sqrt(a^2 - u^2): the column at u holds v from
    // lo = max(v0, -s) to hi = min(v1, s). Between the u where a bound switches from the cell's
    // edge to the circle, each bound is c0 + c1 s (c1 = 0 or +-1), and the integrals of
    // 1, u, s, u s and s^2 over u have closed forms.
    DiscMoments m;
    const double v0 = y0 - cy, v1 = y1 - cy;
    const double u0 = std::max(x0 - cx, -a), u1 = std::min(x1 - cx, a);
    if (u1 <= u0 || v1 <= -a || v0 >= a) return m;
    double cuts[6] = {u0, u1};
    int n = 2;
    for (double v : {v0, v1})
        if (std::fabs(v) < a) {
            const double ub = std::sqrt(a * a - v * v);
            for (double c : {-ub, ub})
                if (c > u0 && c < u1) cuts[n++] = c;
        }
    for (int i = 1; i < n; ++i)  // at most 6: insertion (std::sort here trips GCC 12's -Warray-bounds)
        for (int j = i; j > 0 && cuts[j] < cuts[j - 1]; --j) std::swap(cuts[j], cuts[j - 1]);
    const double a2 = a * a;
    auto s = [a2](double u) { return std::sqrt(std::max(0.0, a2 - u * u)); };
    auto F = [&](double u) { return 0.5 * (u * s(u) + a2 * std::asin(std::clamp(u / a, -1.0, 1.0))); };  // int s
    auto G = [&](double u) { return -std::pow(s(u), 3) / 3; };                                           // int u s
    auto P = [a2](double u) { return a2 * u - u * u * u / 3; };                                           // int s^2
    double area = 0, mu = 0, mv = 0;
    for (int k = 0; k + 1 < n; ++k) {
        const double p = cuts[k], q = cuts[k + 1];
        if (q <= p) continue;
        const double sm = s(0.5 * (p + q));
        const double h0 = sm < v1 ? 0.0 : v1, h1 = sm < v1 ? 1.0 : 0.0;     // hi = h0 + h1 s
        const double l0 = -sm > v0 ? 0.0 : v0, l1 = -sm > v0 ? -1.0 : 0.0;  // lo = l0 + l1 s
        if (h0 + h1 * sm <= l0 + l1 * sm) continue;                          // the column is empty here
        const double I0 = q - p, Iu = 0.5 * (q * q - p * p), Is = F(q) - F(p), Ius = G(q) - G(p), Is2 = P(q) - P(p);
        const double c0 = h0 - l0, c1 = h1 - l1;
        area += c0 * I0 + c1 * Is;
        mu += c0 * Iu + c1 * Ius;
        mv += 0.5 * ((h0 * h0 - l0 * l0) * I0 + 2 * (h0 * h1 - l0 * l1) * Is + (h1 * h1 - l1 * l1) * Is2);
    }
    m.area = area;
    m.mx = mu + cx * area;
    m.my = mv + cy * area;
    return m;
}

double sieve_transmission(const SieveDesign& d, double R, double x, double y) {
    bool open = false;
    nearby_holes(d, R, x, y, 0.0, [&](double hx, double hy, double a) {
        open = open || (x - hx) * (x - hx) + (y - hy) * (y - hy) < a * a;
    });
    return open ? 1.0 : 0.0;
}

double sieve_open_area_in_cell(const SieveDesign& d, double R, const ApertureCell& cell, double& cx, double& cy) {
    const double x0 = cell.x0, x1 = cell.x1, y0 = cell.y0, y1 = cell.y1;
    // Holes never overlap (check_sieve), so the open area is the sum of each hole's share.
    DiscMoments sum;
    const double reach = 0.5 * std::hypot(x1 - x0, y1 - y0);
    nearby_holes(d, R, 0.5 * (x0 + x1), 0.5 * (y0 + y1), reach, [&](double hx, double hy, double a) {
        const DiscMoments m = disc_in_cell(hx, hy, a, cell);
        sum.area += m.area;
        sum.mx += m.mx;
        sum.my += m.my;
    });
    if (sum.area <= 0) return 0.0;
    cx = sum.mx / sum.area;
    cy = sum.my / sum.area;
    return sum.area;
}

double sieve_area(const SieveDesign& d, double R) {
    const double r1 = sieve_centre_radius(d);
    double area = M_PI * r1 * r1;
    for (const SieveRing& r : sieve_rings(d)) area += r.holes * M_PI * r.hole_radius * r.hole_radius;
    return area * R * R;
}

double sieve_bounding_radius(const SieveDesign& d, double R) {
    double reach = sieve_centre_radius(d);
    for (const SieveRing& r : sieve_rings(d)) reach = std::max(reach, r.radius + r.hole_radius);
    return reach * R;
}

double sieve_smallest_hole(const SieveDesign& d, double R) {
    double smallest = 2 * sieve_centre_radius(d);
    for (const SieveRing& r : sieve_rings(d)) smallest = std::min(smallest, 2 * r.hole_radius);
    return smallest * R;
}

}  // namespace wavecam
