#include "subdivision.h"
#include <memory>
#include <string>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

namespace wavecam::trace {

namespace {
namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

// The primvar interface Far's PrimvarRefiner interpolates with.
struct Point {
    Vec3 p;
    void Clear() { p = {}; }
    void AddWithWeight(const Point& src, float weight) { p += src.p * weight; }
};
}  // namespace

Result<RefinedSurface> catmull_clark(const PolygonMesh& cage, int level) {
    if (level < 1) return Result<RefinedSurface>::failure("subdivision level must be at least 1");
    std::size_t corners = 0;
    for (int size : cage.face_sizes) corners += static_cast<std::size_t>(size);
    if (corners != cage.indices.size()) return Result<RefinedSurface>::failure("cage face sizes do not match its index count");
    for (int i : cage.indices)
        if (i < 0 || static_cast<std::size_t>(i) >= cage.positions.size())
            return Result<RefinedSurface>::failure("cage face index " + std::to_string(i) + " names no vertex");
    Far::TopologyDescriptor descriptor;
    descriptor.numVertices = static_cast<int>(cage.positions.size());
    descriptor.numFaces = static_cast<int>(cage.face_sizes.size());
    descriptor.numVertsPerFace = cage.face_sizes.data();
    descriptor.vertIndicesPerFace = cage.indices.data();

    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::unique_ptr<Far::TopologyRefiner> refiner(
        Factory::Create(descriptor, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
    if (!refiner) return Result<RefinedSurface>::failure("OpenSubdiv rejected the cage topology");

    Far::TopologyRefiner::UniformOptions uniform(level);
    uniform.fullTopologyInLastLevel = true;  // face-vertex lists of the last level
    refiner->RefineUniform(uniform);

    // Interpolate positions level by level, then project the last level to the limit.
    std::vector<Point> points(refiner->GetNumVerticesTotal());
    for (std::size_t i = 0; i < cage.positions.size(); ++i) points[i].p = cage.positions[i];
    Far::PrimvarRefiner primvar(*refiner);
    Point* src = points.data();
    for (int l = 1; l <= level; ++l) {
        Point* dst = src + refiner->GetLevel(l - 1).GetNumVertices();
        primvar.Interpolate(l, src, dst);
        src = dst;
    }
    const Far::TopologyLevel& last = refiner->GetLevel(level);
    const int n = last.GetNumVertices();
    std::vector<Point> limit(n), du(n), dv(n);
    Point *limit_out = limit.data(), *du_out = du.data(), *dv_out = dv.data();
    primvar.Limit(src, limit_out, du_out, dv_out);

    RefinedSurface out;
    out.quads.positions.reserve(n);
    out.normals.reserve(n);
    for (int i = 0; i < n; ++i) {
        out.quads.positions.push_back(limit[i].p);
        const Vec3 normal = cross(du[i].p, dv[i].p);
        const double len = length(normal);
        out.normals.push_back(len > 0 ? normal / len : Vec3{0, 0, 0});
    }
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        const Far::ConstIndexArray corners = last.GetFaceVertices(f);
        out.quads.face_sizes.push_back(corners.size());
        for (int c = 0; c < corners.size(); ++c) out.quads.indices.push_back(corners[c]);
    }
    return Result<RefinedSurface>::success(std::move(out));
}

}  // namespace wavecam::trace
