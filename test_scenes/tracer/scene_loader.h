// Reads a scene file (TOML). Layout, all lengths in metres, colours linear RGB:
//
//   [camera]  position, look_at, up = [0,1,0], fov (horizontal, degrees), width, height,
//             samples (per pixel)
//   [sky]     color = [r,g,b] (constant) or zenith = [..] and horizon = [..] (gradient)
//   [[object]] type = "sphere" (center, radius) | "plane" (point, normal, texture_size = 1)
//             | "quad" (corner, edge_u, edge_v) | "box" (min, max, rotate_y = 0 degrees)
//             | "mesh" (obj, scale = 1, translate = [0,0,0])
//             | "subdivision" (level, and obj or inline positions = [[x,y,z],..] with
//               faces = [[i,j,k,l],..] (0-based); scale, translate)
//             and for every object albedo = [r,g,b] (default 0.8 grey) and optionally
//             texture = { type = "checker" | "bars" | "star" | "text", ink = [r,g,b],
//                         count = n, text = "..." }
//   [[light]] type = "point" (position, intensity = [r,g,b] W/sr) | "area" (corner, edge_u,
//             edge_v, radiance = [r,g,b]; emits towards edge_u x edge_v)
//
// Any unknown table or key is an error. Relative OBJ paths are relative to the scene file.
#pragma once
#include <string>
#include "wavecam/result.h"
#include "scene.h"

namespace wavecam::trace {

// Errors are one line: "FILE: WHERE: what is wrong", WHERE naming the table and key.
Result<Scene> load_scene(const std::string& path);

}  // namespace wavecam::trace
