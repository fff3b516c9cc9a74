#include "render.h"
#include <array>
#include <cmath>
#include <numeric>
#include "random.h"
#include "shading.h"
#include "sky.h"

namespace wavecam::trace {

namespace {
// The 2D sample dimensions of one pixel sample: image position, pinhole point, area-light
// point, sky direction. Each is stratified over the same g x g grid, the strata of each
// dimension shuffled independently so the dimensions pair up randomly (Shirley's
// "padding" of stratified samples).
enum Dimension { kImage, kPinhole, kAreaLight, kSky, kDimensions };

class StratifiedSamples {
public:
    StratifiedSamples(int samples, Random& random)
        : grid_(static_cast<int>(std::sqrt(static_cast<double>(samples)))), random_(random) {
        for (std::vector<int>& order : order_) {
            order.resize(static_cast<std::size_t>(grid_) * grid_);
            std::iota(order.begin(), order.end(), 0);
            for (int k = static_cast<int>(order.size()) - 1; k > 0; --k)  // Fisher-Yates
                std::swap(order[k], order[static_cast<int>(random_.uniform() * (k + 1))]);
        }
    }
    // Sample s of dimension d in [0,1)^2: jittered in its stratum, or uniform for the
    // samples beyond g^2.
    std::array<double, 2> get(int s, Dimension d) {
        if (s >= grid_ * grid_) return {random_.uniform(), random_.uniform()};
        const int cell = order_[d][s];
        return {(cell % grid_ + random_.uniform()) / grid_, (cell / grid_ + random_.uniform()) / grid_};
    }

private:
    int grid_;
    Random& random_;
    std::array<std::vector<int>, kDimensions> order_;
};

Vec3 pixel_radiance(const Scene& scene, const TraceScene& geometry, const Camera& camera, const FinitePinhole& pinhole,
                    int samples, int i, int j, Random& random) {
    StratifiedSamples strata(samples, random);
    Vec3 sum;
    for (int s = 0; s < samples; ++s) {
        const auto image = strata.get(s, kImage), hole = strata.get(s, kPinhole);
        const Ray ray = pinhole_ray(camera, pinhole, {i + image[0], j + image[1]}, hole[0], hole[1]);
        const std::optional<SurfaceHit> hit = geometry.intersect(ray);
        if (!hit) {
            sum += sky_radiance(scene.sky, normalize(ray.direction));
            continue;
        }
        const auto area = strata.get(s, kAreaLight), sky = strata.get(s, kSky);
        sum += shade(scene, geometry, *hit, {area[0], area[1], sky[0], sky[1]});
    }
    return sum / samples;
}

// Along the unnormalised direction D + x R + y U (unit D, R and U orthogonal to it) the
// ray parameter t of the ideal pinhole's ray is the planar depth itself.
float centre_depth(const TraceScene& geometry, const Camera& camera, int i, int j) {
    const Ray ray{camera.position(), camera.direction({i + 0.5, j + 0.5})};
    const std::optional<SurfaceHit> hit = geometry.intersect(ray);
    return hit ? static_cast<float>(hit->t) : kSkyDepth;
}
}  // namespace

RenderedImage render(const Scene& scene, const TraceScene& geometry, const Camera& camera,
                     const FinitePinhole& pinhole, int samples) {
    RenderedImage image;
    image.width = camera.width();
    image.height = camera.height();
    image.rgb.resize(3 * static_cast<std::size_t>(image.width) * image.height);
    image.depth.resize(static_cast<std::size_t>(image.width) * image.height);
#pragma omp parallel for schedule(dynamic, 1)
    for (int j = 0; j < image.height; ++j) {
        for (int i = 0; i < image.width; ++i) {
            const std::size_t index = static_cast<std::size_t>(j) * image.width + i;
            Random random(index);
            const Vec3 L = pixel_radiance(scene, geometry, camera, pinhole, samples, i, j, random);
            image.rgb[3 * index] = static_cast<float>(L.x);
            image.rgb[3 * index + 1] = static_cast<float>(L.y);
            image.rgb[3 * index + 2] = static_cast<float>(L.z);
            image.depth[index] = centre_depth(geometry, camera, i, j);
        }
    }
    return image;
}

}  // namespace wavecam::trace
