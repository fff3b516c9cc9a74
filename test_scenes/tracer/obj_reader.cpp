#include "obj_reader.h"
#include <fstream>
#include <sstream>

namespace wavecam::trace {

namespace {
// OBJ statements we accept and ignore (they do not change the polygons).
bool ignored_statement(const std::string& s) {
    return s == "vt" || s == "vn" || s == "o" || s == "g" || s == "s" || s == "usemtl" || s == "mtllib";
}
}  // namespace

Result<PolygonMesh> read_obj(const std::string& path) {
    std::ifstream in(path);
    if (!in) return Result<PolygonMesh>::failure(path + ": cannot open the OBJ file");
    PolygonMesh mesh;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        const std::string where = path + ":" + std::to_string(number) + ": ";
        std::istringstream words(line);
        std::string statement;
        if (!(words >> statement) || statement[0] == '#' || ignored_statement(statement)) continue;
        if (statement == "v") {
            Vec3 p;
            if (!(words >> p.x >> p.y >> p.z)) return Result<PolygonMesh>::failure(where + "expected 'v x y z'");
            mesh.positions.push_back(p);
        } else if (statement == "f") {
            int count = 0;
            for (std::string corner; words >> corner; ++count) {
                int index = 0;
                try {
                    index = std::stoi(corner);  // stops at the first '/'
                } catch (const std::exception&) {
                    return Result<PolygonMesh>::failure(where + "bad face index '" + corner + "'");
                }
                const int n = static_cast<int>(mesh.positions.size());
                const int resolved = index < 0 ? n + index : index - 1;  // negative: relative
                if (index == 0 || resolved < 0 || resolved >= n)
                    return Result<PolygonMesh>::failure(where + "face index " + corner + " names no vertex defined so far");
                mesh.indices.push_back(resolved);
            }
            if (count < 3) return Result<PolygonMesh>::failure(where + "a face needs at least 3 vertices");
            mesh.face_sizes.push_back(count);
        } else {
            return Result<PolygonMesh>::failure(where + "unsupported statement '" + statement + "'");
        }
    }
    if (mesh.face_sizes.empty()) return Result<PolygonMesh>::failure(path + ": no faces");
    return Result<PolygonMesh>::success(std::move(mesh));
}

}  // namespace wavecam::trace
