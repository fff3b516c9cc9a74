// Reads the polygons of a Wavefront OBJ file: `v x y z` and `f i j k ...` lines (indices
// 1-based or negative, `i/t/n` forms accepted, texture coordinates and normals ignored).
#pragma once
#include <string>
#include "polygon_mesh.h"
#include "wavecam/result.h"

namespace wavecam::trace {

// Errors name the file and line.
Result<PolygonMesh> read_obj(const std::string& path);

}  // namespace wavecam::trace
