// A polygon mesh in OBJ's layout: positions, the vertex count of each face, and the
// concatenated vertex indices (0-based) of all faces.
#pragma once
#include <vector>
#include "vec3.h"

namespace wavecam::trace {

struct PolygonMesh {
    std::vector<Vec3> positions;
    std::vector<int> face_sizes;
    std::vector<int> indices;
};

// p -> p * scale + translate for every position.
inline void scale_and_translate(PolygonMesh& mesh, double scale, Vec3 translate) {
    for (Vec3& p : mesh.positions) p = p * scale + translate;
}

}  // namespace wavecam::trace
