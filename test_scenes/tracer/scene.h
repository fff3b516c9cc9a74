// What a scene file describes, in world units (metres), right-handed, +y up.
#pragma once
#include <string>
#include <variant>
#include <vector>
#include "camera.h"
#include "polygon_mesh.h"
#include "texture.h"
#include "vec3.h"

namespace wavecam::trace {

// Diffuse (Lambertian) surface: reflectance albedo, optionally patterned with an ink colour.
struct Material {
    Vec3 albedo{0.8, 0.8, 0.8};
    Texture texture;
};

struct Sphere {
    Vec3 centre;
    double radius = 1;
};
// Infinite plane through `point`; textures repeat every `texture_size` metres.
struct Plane {
    Vec3 point;
    Vec3 normal{0, 1, 0};
    double texture_size = 1;
};
// Parallelogram corner + s edge_u + t edge_v, (s, t) in [0,1]^2 (also its texture coordinates).
struct Quad {
    Vec3 corner, edge_u, edge_v;
};
// Box between two corners, turned by rotate_y degrees (right-handed) about its centre.
struct Box {
    Vec3 min, max;
    double rotate_y_deg = 0;
};
// Polygons as given (an OBJ file); drawn flat-shaded.
struct PolygonObject {
    PolygonMesh mesh;
};
// Catmull-Clark limit approximated by `level` refinements of the cage; drawn smooth-shaded.
struct SubdivisionSurface {
    PolygonMesh cage;
    int level = 3;
};
using Shape = std::variant<Sphere, Plane, Quad, Box, PolygonObject, SubdivisionSurface>;

struct Object {
    Shape shape;
    Material material;
};

// Isotropic point source of radiant intensity I (per channel): irradiance I cos(theta) / r^2.
struct PointLight {
    Vec3 position;
    Vec3 intensity;
};
// One-sided rectangle emitting radiance L towards normalize(edge_u x edge_v); not seen by
// camera rays, sampled uniformly over its area.
struct AreaLight {
    Vec3 corner, edge_u, edge_v;
    Vec3 radiance;
};
// Sky radiance for rays that hit nothing: horizon colour at y = 0 blending linearly in the
// direction's y to zenith colour at y = 1 (below the horizon: horizon colour). Constant sky:
// both equal. The sky also lights the scene (one bounce, shadowed).
struct Sky {
    Vec3 zenith, horizon;
};

struct Scene {
    std::string name;  // the scene file's name, for the output header
    CameraSettings camera;
    int samples_per_pixel = 16;
    std::vector<Object> objects;
    std::vector<PointLight> point_lights;
    std::vector<AreaLight> area_lights;
    Sky sky;
};

}  // namespace wavecam::trace
