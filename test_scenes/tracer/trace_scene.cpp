#include "trace_scene.h"
#include <algorithm>
#include <cmath>
#include <string>
#include <embree3/rtcore.h>
#include <limits>
#include "analytic_shapes.h"
#include "subdivision.h"

namespace wavecam::trace {

// Planes are infinite; Embree needs finite bounds, so they get a cube this big (metres).
constexpr double kPlaneExtent = 1e6;

enum class SurfaceKind { Sphere, Plane, Quads, Triangles };

struct SurfaceRecord {
    SurfaceKind kind;
    Material material;
    Sphere sphere;
    Plane plane;
    Vec3 plane_u, plane_v;              // unit texture axes in the plane
    std::vector<unsigned> quad_indices;  // Quads with smooth normals only
    std::vector<Vec3> vertex_normals;    // empty: flat shading with Embree's Ng
};

struct TraceScene::Embree {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ~Embree() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

namespace {

double analytic_t(const SurfaceRecord& s, Vec3 o, Vec3 d, double t_min, double t_max) {
    if (s.kind == SurfaceKind::Sphere) return intersect_sphere(o, d, s.sphere.centre, s.sphere.radius, t_min, t_max);
    return intersect_plane(o, d, s.plane.point, s.plane.normal, t_min, t_max);
}

void analytic_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* s = static_cast<const SurfaceRecord*>(args->geometryUserPtr);
    const Vec3 c = s->kind == SurfaceKind::Sphere ? s->sphere.centre : Vec3{};
    const double r = s->kind == SurfaceKind::Sphere ? s->sphere.radius : kPlaneExtent;
    RTCBounds* b = args->bounds_o;
    b->lower_x = static_cast<float>(c.x - r), b->lower_y = static_cast<float>(c.y - r);
    b->lower_z = static_cast<float>(c.z - r), b->upper_x = static_cast<float>(c.x + r);
    b->upper_y = static_cast<float>(c.y + r), b->upper_z = static_cast<float>(c.z + r);
}

// rtcIntersect1 / rtcOccluded1 only: N = 1 and the ray is a plain RTCRayHit / RTCRay.
void analytic_intersect(const RTCIntersectFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* s = static_cast<const SurfaceRecord*>(args->geometryUserPtr);
    auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);
    RTCRay& ray = rh->ray;
    const Vec3 o{ray.org_x, ray.org_y, ray.org_z}, d{ray.dir_x, ray.dir_y, ray.dir_z};
    const double t = analytic_t(*s, o, d, ray.tnear, ray.tfar);
    if (t < 0) return;
    const Vec3 n = s->kind == SurfaceKind::Sphere ? o + d * t - s->sphere.centre : s->plane.normal;
    ray.tfar = static_cast<float>(t);
    rh->hit.Ng_x = static_cast<float>(n.x), rh->hit.Ng_y = static_cast<float>(n.y);
    rh->hit.Ng_z = static_cast<float>(n.z);
    rh->hit.u = rh->hit.v = 0;
    rh->hit.primID = args->primID;
    rh->hit.geomID = args->geomID;
    rh->hit.instID[0] = args->context->instID[0];
}

void analytic_occluded(const RTCOccludedFunctionNArguments* args) {
    if (!args->valid[0]) return;
    const auto* s = static_cast<const SurfaceRecord*>(args->geometryUserPtr);
    auto* ray = reinterpret_cast<RTCRay*>(args->ray);
    const Vec3 o{ray->org_x, ray->org_y, ray->org_z}, d{ray->dir_x, ray->dir_y, ray->dir_z};
    if (analytic_t(*s, o, d, ray->tnear, ray->tfar) >= 0) ray->tfar = -std::numeric_limits<float>::infinity();
}

RTCGeometry analytic_geometry(RTCDevice device, SurfaceRecord* record) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, 1);
    rtcSetGeometryUserData(g, record);
    rtcSetGeometryBoundsFunction(g, analytic_bounds, nullptr);
    rtcSetGeometryIntersectFunction(g, analytic_intersect);
    rtcSetGeometryOccludedFunction(g, analytic_occluded);
    return g;
}

// Quads (4 indices each) or triangles (3 each) over `positions`.
RTCGeometry mesh_geometry(RTCDevice device, const std::vector<Vec3>& positions, const std::vector<unsigned>& indices,
                          int corners) {
    RTCGeometry g = rtcNewGeometry(device, corners == 4 ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), positions.size()));
    for (std::size_t i = 0; i < positions.size(); ++i) {
        v[3 * i] = static_cast<float>(positions[i].x);
        v[3 * i + 1] = static_cast<float>(positions[i].y);
        v[3 * i + 2] = static_cast<float>(positions[i].z);
    }
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0,
                                                               corners == 4 ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3,
                                                               corners * sizeof(unsigned), indices.size() / corners));
    std::copy(indices.begin(), indices.end(), idx);
    return g;
}

// Parallelograms corner, +edge_u, +edge_u+edge_v, +edge_v: Embree's quad (u, v) is then the
// position along the edges (p0 base, u towards p1, v towards p3), our texture coordinates.
void add_parallelogram(std::vector<Vec3>& positions, std::vector<unsigned>& indices, Vec3 corner, Vec3 eu, Vec3 ev) {
    const auto base = static_cast<unsigned>(positions.size());
    positions.insert(positions.end(), {corner, corner + eu, corner + eu + ev, corner + ev});
    indices.insert(indices.end(), {base, base + 1, base + 2, base + 3});
}

// Six faces of the box, turned right-handedly about +y through its centre
// (x' = x cos a + z sin a, z' = -x sin a + z cos a); each face's u runs to the right and v up
// as seen from outside (top: v towards -z).
void add_box(std::vector<Vec3>& positions, std::vector<unsigned>& indices, const Box& box) {
    const Vec3 centre = (box.min + box.max) * 0.5, half = (box.max - box.min) * 0.5;
    const double a = box.rotate_y_deg * M_PI / 180, c = std::cos(a), s = std::sin(a);
    auto turn = [&](Vec3 p) { return Vec3{p.x * c + p.z * s, p.y, -p.x * s + p.z * c}; };
    const Vec3 ex = turn({2 * half.x, 0, 0}), ey = {0, 2 * half.y, 0}, ez = turn({0, 0, 2 * half.z});
    const Vec3 lo = centre + turn(-half);
    add_parallelogram(positions, indices, lo + ez, ex, ey);            // +z
    add_parallelogram(positions, indices, lo + ex, -ex, ey);           // -z
    add_parallelogram(positions, indices, lo + ex + ez, -ez, ey);      // +x
    add_parallelogram(positions, indices, lo, ez, ey);                 // -x
    add_parallelogram(positions, indices, lo + ey + ez, ex, -ez);      // +y
    add_parallelogram(positions, indices, lo, ex, ez);                 // -y
}

// Polygons split into fans of triangles (exact for the convex faces OBJ files carry).
std::vector<unsigned> fan_triangles(const PolygonMesh& mesh) {
    std::vector<unsigned> out;
    std::size_t first = 0;
    for (int size : mesh.face_sizes) {
        for (int k = 1; k + 1 < size; ++k) {
            out.push_back(static_cast<unsigned>(mesh.indices[first]));
            out.push_back(static_cast<unsigned>(mesh.indices[first + k]));
            out.push_back(static_cast<unsigned>(mesh.indices[first + k + 1]));
        }
        first += static_cast<std::size_t>(size);
    }
    return out;
}

// Texture axes of a plane: for normal +y, u = +x and v = -z; for normal +z, u = +x, v = +y.
void plane_axes(const Vec3 n, Vec3& u, Vec3& v) {
    const Vec3 helper = std::abs(n.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{0, 0, -1};
    u = normalize(cross(helper, n));
    v = cross(n, u);
}

// Builds the Embree geometry for one object and fills its record; errors say what failed.
Result<RTCGeometry> make_geometry(RTCDevice device, const Shape& shape, SurfaceRecord& r) {
    std::vector<Vec3> positions;
    std::vector<unsigned> indices;
    if (const auto* sphere = std::get_if<Sphere>(&shape)) {
        r.kind = SurfaceKind::Sphere;
        r.sphere = *sphere;
        return Result<RTCGeometry>::success(analytic_geometry(device, &r));
    }
    if (const auto* plane = std::get_if<Plane>(&shape)) {
        r.kind = SurfaceKind::Plane;
        r.plane = *plane;
        r.plane.normal = normalize(plane->normal);
        plane_axes(r.plane.normal, r.plane_u, r.plane_v);
        return Result<RTCGeometry>::success(analytic_geometry(device, &r));
    }
    if (const auto* quad = std::get_if<Quad>(&shape)) {
        r.kind = SurfaceKind::Quads;
        add_parallelogram(positions, indices, quad->corner, quad->edge_u, quad->edge_v);
        return Result<RTCGeometry>::success(mesh_geometry(device, positions, indices, 4));
    }
    if (const auto* box = std::get_if<Box>(&shape)) {
        r.kind = SurfaceKind::Quads;
        add_box(positions, indices, *box);
        return Result<RTCGeometry>::success(mesh_geometry(device, positions, indices, 4));
    }
    if (const auto* polygons = std::get_if<PolygonObject>(&shape)) {
        r.kind = SurfaceKind::Triangles;
        return Result<RTCGeometry>::success(mesh_geometry(device, polygons->mesh.positions, fan_triangles(polygons->mesh), 3));
    }
    const auto& subdivision = std::get<SubdivisionSurface>(shape);
    Result<RefinedSurface> refined = catmull_clark(subdivision.cage, subdivision.level);
    if (!refined.ok()) return Result<RTCGeometry>::failure(refined.error);
    r.kind = SurfaceKind::Quads;
    r.quad_indices.assign(refined.value.quads.indices.begin(), refined.value.quads.indices.end());
    r.vertex_normals = refined.value.normals;
    return Result<RTCGeometry>::success(mesh_geometry(device, refined.value.quads.positions, r.quad_indices, 4));
}

// Texture coordinates: spheres by longitude/latitude (u = 0.5 + atan2(x, z) / 2 pi,
// v = 0.5 + asin(y) / pi of the unit normal), planes along their axes in texture_size units,
// meshes Embree's per-primitive (u, v).
void texture_uv(const SurfaceRecord& s, Vec3 p, const RTCHit& hit, double& u, double& v) {
    if (s.kind == SurfaceKind::Sphere) {
        const Vec3 n = (p - s.sphere.centre) / s.sphere.radius;
        u = 0.5 + std::atan2(n.x, n.z) / (2 * M_PI);
        v = 0.5 + std::asin(std::clamp(n.y, -1.0, 1.0)) / M_PI;
    } else if (s.kind == SurfaceKind::Plane) {
        u = dot(p - s.plane.point, s.plane_u) / s.plane.texture_size;
        v = dot(p - s.plane.point, s.plane_v) / s.plane.texture_size;
    } else {
        u = hit.u;
        v = hit.v;
    }
}

// Smooth normal inside a quad, bilinear in Embree's (u, v): corners p0 (0,0), p1 (1,0),
// p2 (1,1), p3 (0,1).
Vec3 smooth_normal(const SurfaceRecord& s, const RTCHit& hit) {
    const unsigned* q = &s.quad_indices[4 * static_cast<std::size_t>(hit.primID)];
    const double u = hit.u, v = hit.v;
    return s.vertex_normals[q[0]] * ((1 - u) * (1 - v)) + s.vertex_normals[q[1]] * (u * (1 - v)) +
           s.vertex_normals[q[2]] * (u * v) + s.vertex_normals[q[3]] * ((1 - u) * v);
}

// Embree's ray o + t d for 0 < t < t_far, seeing every geometry (RTCRay's fields in order:
// origin, tnear, direction, time, tfar, mask, id, flags).
RTCRay embree_ray(Vec3 o, Vec3 d, float t_far) {
    const auto f = [](double x) { return static_cast<float>(x); };
    return {f(o.x), f(o.y), f(o.z), 0, f(d.x), f(d.y), f(d.z), 0, t_far, ~0u, 0, 0};
}

}  // namespace

TraceScene::TraceScene() : embree_(std::make_unique<Embree>()) {}
TraceScene::~TraceScene() = default;

Result<std::unique_ptr<TraceScene>> TraceScene::build(const Scene& scene) {
    std::unique_ptr<TraceScene> out(new TraceScene());
    Embree& e = *out->embree_;
    e.device = rtcNewDevice(nullptr);
    if (!e.device) return Result<std::unique_ptr<TraceScene>>::failure("Embree: cannot create a device");
    e.scene = rtcNewScene(e.device);
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        auto record = std::make_unique<SurfaceRecord>();
        record->material = scene.objects[i].material;
        Result<RTCGeometry> g = make_geometry(e.device, scene.objects[i].shape, *record);
        if (!g.ok()) return Result<std::unique_ptr<TraceScene>>::failure("object " + std::to_string(i + 1) + ": " + g.error);
        rtcCommitGeometry(g.value);
        const unsigned id = rtcAttachGeometry(e.scene, g.value);
        rtcReleaseGeometry(g.value);
        if (id != out->surfaces_.size()) return Result<std::unique_ptr<TraceScene>>::failure("Embree: unexpected geometry id");
        out->surfaces_.push_back(std::move(record));
    }
    rtcCommitScene(e.scene);
    if (rtcGetDeviceError(e.device) != RTC_ERROR_NONE) return Result<std::unique_ptr<TraceScene>>::failure("Embree: building the scene failed");
    return Result<std::unique_ptr<TraceScene>>::success(std::move(out));
}

std::optional<SurfaceHit> TraceScene::intersect(const Ray& ray) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    rh.ray = embree_ray(ray.origin, ray.direction, std::numeric_limits<float>::infinity());
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(embree_->scene, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;

    const SurfaceRecord& s = *surfaces_[rh.hit.geomID];
    SurfaceHit h;
    h.t = rh.ray.tfar;
    h.position = ray.origin + ray.direction * h.t;
    h.geometric = normalize(Vec3{rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z});
    if (dot(h.geometric, ray.direction) > 0) h.geometric = -h.geometric;  // two-sided
    h.normal = h.geometric;
    if (!s.vertex_normals.empty()) {
        const Vec3 n = smooth_normal(s, rh.hit);
        if (length(n) > 0) h.normal = normalize(dot(n, h.geometric) < 0 ? -n : n);
    }
    double u, v;
    texture_uv(s, h.position, rh.hit, u, v);
    h.albedo = textured_albedo(s.material.albedo, s.material.texture, u, v);
    return h;
}

bool TraceScene::occluded(Vec3 origin, Vec3 direction, double t_max) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray = embree_ray(origin, direction, static_cast<float>(t_max));
    rtcOccluded1(embree_->scene, &context, &ray);
    return ray.tfar < 0;
}

}  // namespace wavecam::trace
