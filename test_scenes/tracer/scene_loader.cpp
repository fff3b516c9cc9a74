#include "scene_loader.h"
#include <filesystem>
#include <set>
#include <sstream>
#include <toml++/toml.h>
#include "bitmap_font.h"
#include "obj_reader.h"

namespace wavecam::trace {

namespace {

// Reads the keys of one TOML table, remembering the first error and which keys were used,
// so that unknown keys can be reported at the end.
class TableReader {
public:
    TableReader(const toml::table& table, std::string where, std::string* error)
        : table_(table), where_(std::move(where)), error_(error) {}

    bool has(const std::string& key) const { return table_.contains(key); }

    double number(const std::string& key, std::optional<double> fallback = std::nullopt) {
        const toml::node* node = find(key, fallback.has_value());
        if (!node) return fallback.value_or(0);
        if (auto v = node->value<double>()) return *v;
        fail(key, "expected a number");
        return 0;
    }
    double positive(const std::string& key, std::optional<double> fallback = std::nullopt) {
        const double v = number(key, fallback);
        if (v <= 0 && error_->empty()) fail(key, "must be positive");
        return v;
    }
    int integer(const std::string& key, int lo, int hi, std::optional<int> fallback = std::nullopt) {
        const toml::node* node = find(key, fallback.has_value());
        if (!node) return fallback.value_or(0);
        const auto v = node->as_integer();
        if (!v || v->get() < lo || v->get() > hi) {
            fail(key, "expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
            return lo;
        }
        return static_cast<int>(v->get());
    }
    std::string string(const std::string& key, std::optional<std::string> fallback = std::nullopt) {
        const toml::node* node = find(key, fallback.has_value());
        if (!node) return fallback.value_or("");
        if (auto v = node->value<std::string>()) return *v;
        fail(key, "expected a string");
        return "";
    }
    Vec3 vec3(const std::string& key, std::optional<Vec3> fallback = std::nullopt) {
        const toml::node* node = find(key, fallback.has_value());
        if (!node) return fallback.value_or(Vec3{});
        Vec3 v;
        if (!to_vec3(*node, v)) fail(key, "expected [x, y, z]");
        return v;
    }
    // A colour: [r, g, b] or one number for grey.
    Vec3 colour(const std::string& key, std::optional<Vec3> fallback = std::nullopt) {
        const toml::node* node = find(key, fallback.has_value());
        if (!node) return fallback.value_or(Vec3{});
        if (auto grey = node->value<double>()) return {*grey, *grey, *grey};
        Vec3 v;
        if (!to_vec3(*node, v) || v.x < 0 || v.y < 0 || v.z < 0) fail(key, "expected [r, g, b] (non-negative)");
        return v;
    }
    // [[x,y,z], ...]
    std::vector<Vec3> vec3_list(const std::string& key) {
        std::vector<Vec3> out;
        const toml::array* array = array_at(key);
        for (std::size_t i = 0; array && i < array->size(); ++i) {
            Vec3 v;
            if (!to_vec3(*array->get(i), v)) fail(key, "entry " + std::to_string(i) + ": expected [x, y, z]");
            out.push_back(v);
        }
        return out;
    }
    // [[i,j,k,...], ...]: face sizes and concatenated indices.
    void face_list(const std::string& key, std::vector<int>& sizes, std::vector<int>& indices) {
        const toml::array* array = array_at(key);
        for (std::size_t f = 0; array && f < array->size(); ++f) {
            const toml::array* face = array->get(f)->as_array();
            if (!face || face->size() < 3) {
                fail(key, "face " + std::to_string(f) + ": expected a list of 3 or more vertex indices");
                return;
            }
            for (const toml::node& index : *face) {
                const auto i = index.as_integer();
                if (!i) {
                    fail(key, "face " + std::to_string(f) + ": indices must be integers");
                    return;
                }
                indices.push_back(static_cast<int>(i->get()));
            }
            sizes.push_back(static_cast<int>(face->size()));
        }
    }
    // The node at `key` as a toml::table or toml::array, else the error "what".
    template <class T>
    const T* typed(const std::string& key, bool optional, const char* what) {
        const toml::node* node = find(key, optional);
        if (!node) return nullptr;
        if (const T* t = node->as<T>()) return t;
        fail(key, what);
        return nullptr;
    }
    // Reports the first key that nothing asked for.
    void finish() {
        for (const auto& [key, node] : table_)
            if (!used_.count(std::string(key.str()))) {
                fail(std::string(key.str()), "unknown key");
                return;
            }
    }
    void fail(const std::string& key, const std::string& what) {
        if (error_->empty()) *error_ = where_ + ": key '" + key + "': " + what;
    }
    const std::string& where() const { return where_; }

private:
    const toml::node* find(const std::string& key, bool optional) {
        used_.insert(key);
        const toml::node* node = table_.get(key);
        if (!node && !optional) fail(key, "missing");
        return node;
    }
    const toml::array* array_at(const std::string& key) { return typed<toml::array>(key, false, "expected a list"); }
    static bool to_vec3(const toml::node& node, Vec3& v) {
        const toml::array* a = node.as_array();
        if (!a || a->size() != 3) return false;
        const auto x = a->get(0)->value<double>(), y = a->get(1)->value<double>(), z = a->get(2)->value<double>();
        if (!x || !y || !z) return false;
        v = {*x, *y, *z};
        return true;
    }

    const toml::table& table_;
    std::string where_;
    std::string* error_;
    std::set<std::string> used_;
};

CameraSettings read_camera(TableReader& r, int& samples) {
    CameraSettings c;
    c.position = r.vec3("position");
    c.look_at = r.vec3("look_at");
    c.up = r.vec3("up", Vec3{0, 1, 0});
    c.fov_deg = r.number("fov");
    if (c.fov_deg <= 0 || c.fov_deg >= 179) r.fail("fov", "expected degrees between 0 and 179");
    c.width = r.integer("width", 1, 16384);
    c.height = r.integer("height", 1, 16384);
    samples = r.integer("samples", 1, 65536, 16);
    const Vec3 forward = c.look_at - c.position;
    if (length(forward) == 0) r.fail("look_at", "equals position");
    else if (length(cross(forward, c.up)) == 0) r.fail("up", "parallel to the view direction");
    return c;
}

Sky read_sky(TableReader& r) {
    if (r.has("color")) {
        const Vec3 c = r.colour("color");
        return {c, c};
    }
    return {r.colour("zenith"), r.colour("horizon")};
}

Texture read_texture(TableReader& r) {
    Texture t;
    const std::string type = r.string("type");
    if (type == "checker") t.kind = TextureKind::Checker;
    else if (type == "bars") t.kind = TextureKind::Bars;
    else if (type == "star") t.kind = TextureKind::SiemensStar;
    else if (type == "text") t.kind = TextureKind::Text;
    else r.fail("type", "expected checker, bars, star or text, not '" + type + "'");
    t.ink = r.colour("ink", t.ink);
    if (t.kind == TextureKind::Text) {
        t.text = r.string("text");
        for (char c : t.text)
            if (!has_glyph(c)) r.fail("text", std::string("no glyph for '") + c + "' (A-Z 0-9 space . - : / =)");
    } else {
        const int fallback = t.kind == TextureKind::Bars ? 6 : t.kind == TextureKind::SiemensStar ? 16 : 8;
        t.count = r.integer("count", 1, 1000, fallback);
    }
    return t;
}

// The polygons of a mesh or cage: from `obj` (relative to the scene file) or inline.
PolygonMesh read_polygons(TableReader& r, const std::filesystem::path& scene_dir, bool allow_inline) {
    PolygonMesh mesh;
    if (r.has("obj") || !allow_inline) {
        const std::filesystem::path file = scene_dir / r.string("obj");
        if (!r.has("obj")) return mesh;
        Result<PolygonMesh> read = read_obj(file.string());
        if (!read.ok()) r.fail("obj", read.error);
        else mesh = std::move(read.value);
    } else {
        mesh.positions = r.vec3_list("positions");
        r.face_list("faces", mesh.face_sizes, mesh.indices);
        for (int i : mesh.indices)
            if (i < 0 || static_cast<std::size_t>(i) >= mesh.positions.size()) {
                r.fail("faces", "index " + std::to_string(i) + " names no entry of positions");
                break;
            }
    }
    scale_and_translate(mesh, r.positive("scale", 1.0), r.vec3("translate", Vec3{}));
    return mesh;
}

Object read_object(TableReader& r, const std::filesystem::path& scene_dir, std::string* error) {
    Object o;
    const std::string type = r.string("type");
    if (type == "sphere") {
        o.shape = Sphere{r.vec3("center"), r.positive("radius")};
    } else if (type == "plane") {
        Plane p{r.vec3("point"), r.vec3("normal"), r.positive("texture_size", 1.0)};
        if (length(p.normal) == 0) r.fail("normal", "must not be zero");
        o.shape = p;
    } else if (type == "quad") {
        o.shape = Quad{r.vec3("corner"), r.vec3("edge_u"), r.vec3("edge_v")};
    } else if (type == "box") {
        Box b{r.vec3("min"), r.vec3("max"), r.number("rotate_y", 0.0)};
        if (b.max.x <= b.min.x || b.max.y <= b.min.y || b.max.z <= b.min.z) r.fail("max", "must exceed min on every axis");
        o.shape = b;
    } else if (type == "mesh") {
        o.shape = PolygonObject{read_polygons(r, scene_dir, false)};
    } else if (type == "subdivision") {
        const int level = r.integer("level", 1, 6);
        o.shape = SubdivisionSurface{read_polygons(r, scene_dir, true), level};
    } else {
        r.fail("type", "expected sphere, plane, quad, box, mesh or subdivision, not '" + type + "'");
    }
    o.material.albedo = r.colour("albedo", o.material.albedo);
    if (const auto* t = r.typed<toml::table>("texture", true, "expected a table { ... }")) {
        TableReader tr(*t, r.where() + ": texture", error);
        o.material.texture = read_texture(tr);
        tr.finish();
    }
    return o;
}

void read_light(TableReader& r, Scene& scene) {
    const std::string type = r.string("type");
    if (type == "point") {
        scene.point_lights.push_back({r.vec3("position"), r.colour("intensity")});
    } else if (type == "area") {
        AreaLight a{r.vec3("corner"), r.vec3("edge_u"), r.vec3("edge_v"), r.colour("radiance")};
        if (length(cross(a.edge_u, a.edge_v)) == 0) r.fail("edge_v", "parallel to edge_u (no area)");
        scene.area_lights.push_back(a);
    } else {
        r.fail("type", "expected point or area, not '" + type + "'");
    }
}

// [[name]] entries, each read by `read(reader)`.
template <class Read>
void for_each_entry(const toml::table& root, const std::string& name, std::string* error, Read read) {
    const toml::node* node = root.get(name);
    if (!node) return;
    const toml::array* array = node->as_array();
    if (!array || !array->is_array_of_tables()) {
        if (error->empty()) *error = "'" + name + "' must be written as [[" + name + "]] tables";
        return;
    }
    for (std::size_t i = 0; i < array->size() && error->empty(); ++i) {
        const toml::table& t = *array->get(i)->as_table();
        const std::string type = t.get("type") && t.get("type")->is_string() ? " (" + **t.get("type")->as_string() + ")" : "";
        TableReader r(t, "[[" + name + "]] " + std::to_string(i + 1) + type, error);
        read(r);
        r.finish();
    }
}

}  // namespace

Result<Scene> load_scene(const std::string& path) {
    if (!std::filesystem::is_regular_file(path)) return Result<Scene>::failure(path + ": no such scene file");
    toml::table root;
    try {
        root = toml::parse_file(path);
    } catch (const toml::parse_error& e) {
        std::ostringstream s;
        s << path << ":" << e.source().begin.line << ":" << e.source().begin.column << ": " << e.description();
        return Result<Scene>::failure(s.str());
    }
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    std::string error;
    Scene scene;
    scene.name = std::filesystem::path(path).filename().string();

    for (const auto& [key, node] : root) {
        const std::string k(key.str());
        if (k != "camera" && k != "sky" && k != "object" && k != "light") {
            error = "unknown table '" + k + "' (camera, sky, [[object]], [[light]])";
            break;
        }
    }
    for (const char* name : {"camera", "sky"}) {
        if (!error.empty()) break;
        const toml::table* t = root.get(name) ? root.get(name)->as_table() : nullptr;
        if (!t) {
            error = std::string("[") + name + "]: missing table";
            break;
        }
        TableReader r(*t, std::string("[") + name + "]", &error);
        if (std::string(name) == "camera") scene.camera = read_camera(r, scene.samples_per_pixel);
        else scene.sky = read_sky(r);
        r.finish();
    }
    if (error.empty())
        for_each_entry(root, "object", &error, [&](TableReader& r) { scene.objects.push_back(read_object(r, dir, &error)); });
    if (error.empty()) for_each_entry(root, "light", &error, [&](TableReader& r) { read_light(r, scene); });
    if (error.empty() && scene.objects.empty()) error = "no [[object]]";
    if (!error.empty()) return Result<Scene>::failure(path + ": " + error);
    return Result<Scene>::success(std::move(scene));
}

}  // namespace wavecam::trace
