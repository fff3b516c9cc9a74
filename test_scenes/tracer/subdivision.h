// Catmull-Clark subdivision surfaces through OpenSubdiv Far: the cage refined uniformly
// `level` times, its vertices then moved onto the limit surface with the limit normals.
#pragma once
#include <vector>
#include "polygon_mesh.h"
#include "wavecam/result.h"

namespace wavecam::trace {

// After one or more Catmull-Clark steps every face is a quad.
struct RefinedSurface {
    PolygonMesh quads;
    std::vector<Vec3> normals;  // unit limit-surface normal per vertex (cross of limit tangents)
};

// level >= 1. A cage of F faces with n_f sides gives sum n_f quads after one step and
// 4x more at each further step.
Result<RefinedSurface> catmull_clark(const PolygonMesh& cage, int level);

}  // namespace wavecam::trace
