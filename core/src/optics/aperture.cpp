#include "wavecam/aperture.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "wavecam/units.h"

namespace wavecam {
namespace {

// Mean of `t` over 16 x 16 sub-cells of `cell` and the t-weighted centroid: the rim-cell rule.
template <class Transmission>
double subsampled_coverage(const Transmission& t, const ApertureCell& cell, double& cx, double& cy) {
    const double x0 = cell.x0, x1 = cell.x1, y0 = cell.y0, y1 = cell.y1;
    constexpr int kSub = 16;
    double sum = 0, sx = 0, sy = 0;
    for (int j = 0; j < kSub; ++j)
        for (int i = 0; i < kSub; ++i) {
            const double px = x0 + (x1 - x0) * (i + 0.5) / kSub;
            const double py = y0 + (y1 - y0) * (j + 0.5) / kSub;
            const double w = t(px, py);
            sum += w;
            sx += w * px;
            sy += w * py;
        }
    if (sum <= 0) return 0.0;
    cx = sx / sum;
    cy = sy / sum;
    return sum / (kSub * kSub);
}

// Nearest and farthest distances of the cell from the origin. (sqrt of the sum of squares, not
// hypot: apertures are millimetres, far from overflow, and hypot's care cost a transfer-function
// pupil grid more than its open fractions did.)
void cell_radii(double x0, double x1, double y0, double y1, double& near, double& far) {
    const double nx = std::clamp(0.0, x0, x1), ny = std::clamp(0.0, y0, y1);
    const double fx = std::max(std::fabs(x0), std::fabs(x1)), fy = std::max(std::fabs(y0), std::fabs(y1));
    near = std::sqrt(nx * nx + ny * ny);
    far = std::sqrt(fx * fx + fy * fy);
}

// Regular N-gon of circumradius r, a vertex at angle `rotation`: inside when the projection on
// the nearest edge normal (at rotation + pi/N + 2 pi k/N) is below the apothem r cos(pi/N).
bool inside_polygon(double x, double y, double r, int sides, double rotation) {
    const double sector = 2 * M_PI / sides;
    const double phi = std::atan2(y, x) - rotation - 0.5 * sector;
    const double off = std::remainder(phi, sector);  // angle from the nearest edge normal
    return std::hypot(x, y) * std::cos(off) < r * std::cos(0.5 * sector);
}

// Zone index n (1-based) of radius rho in a plate of N zones and outer radius r:
// r_(n-1) <= rho < r_n with r_n = r sqrt(n / N).
long zone_of(double rho, double r, int zones) { return long(std::floor(zones * (rho * rho) / (r * r))) + 1; }

std::string shape_list() {
    return "'circle', 'square', 'polygon:N[:ROTATIONdeg]', 'mask:FILE', 'zoneplate:N' or 'sieve:N[:Kx][:FILL%][:SEED]'";
}

}  // namespace

double Aperture::transmission(double x, double y) const {
    const double r = diameter / 2.0;
    switch (shape) {
        case ApertureShape::Circle: return x * x + y * y < r * r ? 1.0 : 0.0;
        case ApertureShape::Square: return std::fabs(x) < r && std::fabs(y) < r ? 1.0 : 0.0;
        case ApertureShape::Polygon: return inside_polygon(x, y, r, sides, rotation) ? 1.0 : 0.0;
        case ApertureShape::ZonePlate: {
            const double rho = std::hypot(x, y);
            return rho < r && zone_of(rho, r, zones) % 2 == 1 ? 1.0 : 0.0;
        }
        case ApertureShape::PhotonSieve: return sieve_transmission(sieve(), r, x, y);
        case ApertureShape::Mask: {
            if (!mask) return 0.0;
            const double p = diameter / mask->width;  // metres per mask pixel
            const double c = std::floor((x + r) / p), row = std::floor((0.5 * mask->height * p - y) / p);
            if (c < 0 || c >= mask->width || row < 0 || row >= mask->height) return 0.0;
            return mask->amplitude[size_t(row) * mask->width + size_t(c)];
        }
    }
    return 0.0;
}

double Aperture::coverage(double x0, double x1, double y0, double y1, double& cx, double& cy) const {
    const double r = diameter / 2.0;
    cx = 0.5 * (x0 + x1);
    cy = 0.5 * (y0 + y1);
    const double cell = (x1 - x0) * (y1 - y0);
    if (shape == ApertureShape::Square) {
        const double ox0 = std::max(x0, -r), ox1 = std::min(x1, r);
        const double oy0 = std::max(y0, -r), oy1 = std::min(y1, r);
        if (ox1 <= ox0 || oy1 <= oy0) return 0.0;
        cx = 0.5 * (ox0 + ox1);
        cy = 0.5 * (oy0 + oy1);
        return (ox1 - ox0) * (oy1 - oy0) / cell;
    }
    if (shape == ApertureShape::PhotonSieve) return sieve_open_area_in_cell(sieve(), r, {x0, x1, y0, y1}, cx, cy) / cell;
    if (shape == ApertureShape::Mask) {
        // Exact integral of the box-sampled image over the cell: each mask pixel is a square of
        // constant transmission; its overlap with the cell adds value x area and moments.
        if (!mask) return 0.0;
        const double p = diameter / mask->width, top = 0.5 * mask->height * p;
        const int c0 = std::max(0, int(std::floor((x0 + r) / p))), c1 = std::min(mask->width - 1, int(std::floor((x1 + r) / p)));
        const int r0 = std::max(0, int(std::floor((top - y1) / p))), r1 = std::min(mask->height - 1, int(std::floor((top - y0) / p)));
        double sum = 0, sx = 0, sy = 0;
        for (int row = r0; row <= r1; ++row)
            for (int c = c0; c <= c1; ++c) {
                const double t = mask->amplitude[size_t(row) * mask->width + c];
                if (t <= 0) continue;
                const double ax0 = std::max(x0, -r + c * p), ax1 = std::min(x1, -r + (c + 1) * p);
                const double ay0 = std::max(y0, top - (row + 1) * p), ay1 = std::min(y1, top - row * p);
                if (ax1 <= ax0 || ay1 <= ay0) continue;
                const double w = t * (ax1 - ax0) * (ay1 - ay0);
                sum += w;
                sx += w * 0.5 * (ax0 + ax1);
                sy += w * 0.5 * (ay0 + ay1);
            }
        if (sum <= 0) return 0.0;
        cx = sx / sum;
        cy = sy / sum;
        return sum / cell;
    }
    // Circle, polygon, zone plate: whole cells inside or outside are decided from the cell's
    // nearest and farthest distances; the rest are sub-sampled.
    double near, far;
    cell_radii(x0, x1, y0, y1, near, far);
    if (near >= r) return 0.0;
    auto t = [this](double x, double y) { return transmission(x, y); };
    switch (shape) {
        case ApertureShape::Circle:
            if (far <= r) return 1.0;
            break;
        case ApertureShape::Polygon:  // convex: all four corners inside means the cell is inside
            if (inside_polygon(x0, y0, r, sides, rotation) && inside_polygon(x1, y0, r, sides, rotation) &&
                inside_polygon(x0, y1, r, sides, rotation) && inside_polygon(x1, y1, r, sides, rotation))
                return 1.0;
            break;
        case ApertureShape::ZonePlate:
            if (far < r && zone_of(near, r, zones) == zone_of(far, r, zones))
                return zone_of(near, r, zones) % 2 == 1 ? 1.0 : 0.0;
            break;
        default: break;
    }
    return subsampled_coverage(t, {x0, x1, y0, y1}, cx, cy);
}

double Aperture::area() const {
    const double r = diameter / 2.0;
    switch (shape) {
        case ApertureShape::Circle: return M_PI * r * r;
        case ApertureShape::Square: return diameter * diameter;
        case ApertureShape::Polygon: return 0.5 * sides * r * r * std::sin(2 * M_PI / sides);
        case ApertureShape::ZonePlate: return M_PI * r * r / zones * double((zones + 1) / 2);  // odd zones, equal areas
        case ApertureShape::PhotonSieve: return sieve_area(sieve(), r);
        case ApertureShape::Mask: {
            if (!mask) return 0.0;
            double sum = 0;
            for (float t : mask->amplitude) sum += double(t) * t;
            const double p = diameter / mask->width;
            return sum * p * p;
        }
    }
    return 0.0;
}

double Aperture::bounding_radius() const {
    switch (shape) {
        case ApertureShape::Square: return 0.5 * diameter * std::sqrt(2.0);
        case ApertureShape::Mask: return mask ? mask->radius * diameter : 0.0;
        case ApertureShape::PhotonSieve: return sieve_bounding_radius(sieve(), 0.5 * diameter);
        default: return 0.5 * diameter;
    }
}

namespace {

// A regular N-gon with a vertex at angle R has mirror lines at R + k pi / N; a mirror line at
// angle phi makes it even across the line at phi (x: phi = pi/2, y: phi = 0).
bool polygon_mirrors_across(int sides, double rotation, double phi) {
    const double k = (phi - rotation) * sides / M_PI;
    return std::fabs(k - std::round(k)) < 1e-9;
}

// A mask's columns (or rows) read the same backwards.
bool mask_even(const TransmissionMask& m, bool columns) {
    for (int r = 0; r < m.height; ++r)
        for (int c = 0; c < m.width; ++c) {
            const int rr = columns ? r : m.height - 1 - r, cc = columns ? m.width - 1 - c : c;
            if (m.amplitude[size_t(r) * m.width + c] != m.amplitude[size_t(rr) * m.width + cc]) return false;
        }
    return true;
}

}  // namespace

bool Aperture::even_in_x() const {
    switch (shape) {
        case ApertureShape::Polygon: return polygon_mirrors_across(sides, rotation, M_PI / 2);
        case ApertureShape::Mask: return mask && mask_even(*mask, true);
        case ApertureShape::PhotonSieve: return false;
        default: return true;  // circle, square, zone plate
    }
}

bool Aperture::even_across_antidiagonal() const {
    switch (shape) {
        case ApertureShape::Polygon: return polygon_mirrors_across(sides, rotation, 3 * M_PI / 4);
        case ApertureShape::Mask:
        case ApertureShape::PhotonSieve: return false;
        default: return true;  // circle, square, zone plate
    }
}

bool Aperture::even_in_y() const {
    switch (shape) {
        case ApertureShape::Polygon: return polygon_mirrors_across(sides, rotation, 0.0);
        case ApertureShape::Mask: return mask && mask_even(*mask, false);
        case ApertureShape::PhotonSieve: return false;
        default: return true;
    }
}

double Aperture::finest_width() const {
    const double r = diameter / 2.0;
    switch (shape) {
        case ApertureShape::PhotonSieve: return sieve_smallest_hole(sieve(), r);
        case ApertureShape::ZonePlate: {  // the last open zone, N or N - 1
            const int n = zones % 2 == 1 ? zones : zones - 1;
            return n > 1 ? r * (std::sqrt(double(n) / zones) - std::sqrt(double(n - 1) / zones)) : diameter;
        }
        default: return diameter;
    }
}

std::string Aperture::name() const {
    std::ostringstream s;
    switch (shape) {
        case ApertureShape::Circle: return "circle";
        case ApertureShape::Square: return "square";
        case ApertureShape::Polygon: s << "polygon:" << sides << ":" << rotation * 180 / M_PI << "deg"; break;
        case ApertureShape::ZonePlate: s << "zoneplate:" << zones; break;
        case ApertureShape::PhotonSieve: s << "sieve:" << zones << ":" << hole_ratio << "x:" << fill * 100 << "%:" << seed; break;
        case ApertureShape::Mask: s << "mask:" << mask_file; break;
    }
    return s.str();
}

double zone_plate_focus(const Aperture& a, double wavelength) {
    return 0.25 * a.diameter * a.diameter / a.zones / wavelength;
}

bool has_zone_focus(const Aperture& a) {
    return a.shape == ApertureShape::ZonePlate || a.shape == ApertureShape::PhotonSieve;
}

Result<Aperture> parse_aperture(const std::string& text, const std::string& field) {
    auto fail = [&field](const std::string& m) { return Result<Aperture>::failure(field + ": " + m); };
    Aperture a;
    const size_t colon = text.find(':');
    const std::string kind = text.substr(0, colon), rest = colon == std::string::npos ? "" : text.substr(colon + 1);
    auto count = [&](const std::string& what, const std::string& v, long lo, long& n) -> std::string {
        char* end = nullptr;
        n = v.empty() ? 0 : std::strtol(v.c_str(), &end, 10);
        if (v.empty() || *end != '\0' || n < lo || n > 100000)
            return "expected " + what + " to be a whole number from " + std::to_string(lo) + " to 100000 in '" +
                   text + "', got '" + v + "'";
        return "";
    };
    if ((kind == "circle" || kind == "square") && colon == std::string::npos) {
        a.shape = kind == "circle" ? ApertureShape::Circle : ApertureShape::Square;
    } else if (kind == "polygon") {
        const size_t second = rest.find(':');
        long n = 0;
        if (auto e = count("the number of sides N", rest.substr(0, second), 3, n); !e.empty()) return fail(e);
        a.shape = ApertureShape::Polygon;
        a.sides = int(n);
        if (second != std::string::npos) {
            auto angle = parse_angle(rest.substr(second + 1), field + " rotation");
            if (!angle.ok()) return Result<Aperture>::failure(angle.error);
            a.rotation = angle.value;
        }
    } else if (kind == "zoneplate") {
        long n = 0;
        if (auto e = count("the number of zones N", rest, 1, n); !e.empty()) return fail(e);
        a.shape = ApertureShape::ZonePlate;
        a.zones = int(n);
    } else if (kind == "sieve") {
        // sieve:N then, in any order, Kx (hole diameter / zone width), FILL% and a seed
        std::vector<std::string> parts;
        for (size_t b = 0, e; b <= rest.size(); b = e + 1) {
            e = std::min(rest.find(':', b), rest.size());
            parts.push_back(rest.substr(b, e - b));
        }
        long n = 0;
        if (auto e = count("the number of zones N", parts[0], 1, n); !e.empty()) return fail(e);
        a.shape = ApertureShape::PhotonSieve;
        a.zones = int(n);
        bool ratio = false, fill = false, seed = false;
        for (size_t k = 1; k < parts.size(); ++k) {
            const std::string& v = parts[k];
            const char last = v.empty() ? '\0' : v.back();
            char* end = nullptr;
            const double x = v.size() > 1 ? std::strtod(v.c_str(), &end) : NAN;
            const bool number = end == v.c_str() + v.size() - 1 && std::isfinite(x);
            if (last == 'x' && !ratio && number) {
                a.hole_ratio = x;
                ratio = true;
            } else if (last == '%' && !fill && number) {
                a.fill = x / 100;
                fill = true;
            } else if (!seed && !v.empty() && v.find_first_not_of("0123456789") == std::string::npos && v.size() <= 10 &&
                       std::stoull(v) <= 0xffffffffull) {
                a.seed = uint32_t(std::stoull(v));
                seed = true;
            } else {
                return fail("expected 'sieve:N' then, once each, a hole diameter in zone widths (e.g. '1.5x'), a fill "
                            "of each ring's circumference (e.g. '50%') and a seed from 0 to 4294967295, got '" + v +
                            "' in '" + text + "'");
            }
        }
        if (auto c = check_sieve(a.sieve(), field); !c.ok()) return Result<Aperture>::failure(c.error + " in '" + text + "'");
    } else if (kind == "mask") {
        if (rest.empty()) return fail("expected an image file after 'mask:', got '" + text + "'");
        a.shape = ApertureShape::Mask;
        a.mask_file = rest;
    } else {
        return fail("expected " + shape_list() + ", got '" + text + "'");
    }
    return Result<Aperture>::success(a);
}

Result<bool> set_aperture_mask(Aperture& aperture, int width, int height, std::vector<float> amplitude,
                               const std::string& field) {
    auto fail = [&](const std::string& m) {
        return Result<bool>::failure(field + ": mask '" + aperture.mask_file + "': " + m);
    };
    if (width < 1 || height < 1 || amplitude.size() != size_t(width) * height)
        return fail("expected a non-empty greyscale image");
    auto m = std::make_shared<TransmissionMask>();
    m->width = width;
    m->height = height;
    bool open = false;
    for (int row = 0; row < height; ++row)
        for (int c = 0; c < width; ++c) {
            const float t = amplitude[size_t(row) * width + c];
            if (!(t >= 0.0f && t <= 1.0f))
                return fail("expected amplitude transmission values from 0 to 1, got " + std::to_string(t) +
                            " at pixel (" + std::to_string(c) + ", " + std::to_string(row) + ")");
            if (t == 0.0f) continue;
            open = true;
            // farthest corner of this pixel from the centre, in mask widths
            const double dx = std::max(std::fabs(c - 0.5 * width), std::fabs(c + 1 - 0.5 * width));
            const double dy = std::max(std::fabs(row - 0.5 * height), std::fabs(row + 1 - 0.5 * height));
            m->radius = std::max(m->radius, std::hypot(dx, dy) / width);
        }
    if (!open) return fail("every pixel is black: the mask lets no light through");
    m->amplitude = std::move(amplitude);
    aperture.mask = std::move(m);
    return Result<bool>::success(true);
}

double sample_pitch(double wavelength, double sin_theta_max) {
    return wavelength / (2.0 * std::clamp(sin_theta_max, 1e-6, 1.0));
}

double resolved_pitch(const Aperture& aperture, double pitch) {
    return std::min(pitch, aperture.finest_width() / kSamplesAcrossFinest);
}

double estimate_sample_count(const Aperture& aperture, double pitch) {
    pitch = resolved_pitch(aperture, pitch);
    return aperture.area() / (pitch * pitch);
}

ApertureSamples sample_aperture(const Aperture& aperture, double pitch) {
    pitch = resolved_pitch(aperture, pitch);
    ApertureSamples s;
    s.pitch = pitch;
    const long n = static_cast<long>(std::ceil(aperture.bounding_radius() / pitch)) + 1;
    const size_t reserve = static_cast<size_t>(estimate_sample_count(aperture, pitch) * 1.05) + 16;
    s.x.reserve(reserve);
    s.y.reserve(reserve);
    s.weight.reserve(reserve);
    const double cell = pitch * pitch;
    for (long j = -n; j <= n; ++j)
        for (long i = -n; i <= n; ++i) {
            double cx, cy;
            const double c = aperture.coverage((i - 0.5) * pitch, (i + 0.5) * pitch, (j - 0.5) * pitch,
                                               (j + 0.5) * pitch, cx, cy);
            if (c <= 0.0) continue;
            s.x.push_back(static_cast<float>(cx));
            s.y.push_back(static_cast<float>(cy));
            s.weight.push_back(static_cast<float>(c * cell));
        }
    return s;
}

}  // namespace wavecam
