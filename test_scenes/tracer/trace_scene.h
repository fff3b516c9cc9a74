// The scene's geometry in Embree 3: spheres and planes as exact user geometry, everything
// else as quads or triangles. Answers what a ray hits and what the surface is like there.
#pragma once
#include <memory>
#include <optional>
#include <vector>
#include "finite_pinhole.h"
#include "wavecam/result.h"
#include "scene.h"

namespace wavecam::trace {

struct SurfaceHit {
    double t = 0;     // ray parameter: position = origin + t direction
    Vec3 position;
    Vec3 normal;      // unit shading normal, on the side the ray came from
    Vec3 geometric;   // unit geometric normal, same side
    Vec3 albedo;      // with the texture applied
};

struct SurfaceRecord;  // per Embree geometry: shape data and material

class TraceScene {
public:
    static Result<std::unique_ptr<TraceScene>> build(const Scene& scene);
    ~TraceScene();
    TraceScene(const TraceScene&) = delete;
    TraceScene& operator=(const TraceScene&) = delete;

    // Nearest hit with t > 0.
    std::optional<SurfaceHit> intersect(const Ray& ray) const;
    // Whether anything lies on origin + t direction for 0 < t < t_max.
    bool occluded(Vec3 origin, Vec3 direction, double t_max) const;

private:
    TraceScene();
    struct Embree;
    std::unique_ptr<Embree> embree_;
    std::vector<std::unique_ptr<SurfaceRecord>> surfaces_;  // index = Embree geometry id
};

}  // namespace wavecam::trace
