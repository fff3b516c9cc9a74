// Tests of wavecam-trace: depths against analytic intersections computed here from the
// camera convention alone, camera projection, subdivision face counts, finite-pinhole rays,
// errors without output, and the camera match with POV-Ray.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>
#include <toml++/toml.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include "camera.h"
#include "finite_pinhole.h"
#include "command_line.h"
#include "subdivision.h"

namespace fs = std::filesystem;
using namespace wavecam::trace;
using wavecam::Result;

namespace {

const std::string kScenes = std::string(WAVECAM_TEST_SCENES_DIR) + "/scenes";
const std::string kTrace = WAVECAM_TRACE_BINARY;

// A fresh empty directory per test.
fs::path scratch_dir(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("wavecam_test_tracer_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// Runs a shell command; returns its exit status, stdout+stderr into `output`.
int run(const std::string& command, std::string& output) {
    const fs::path log = fs::temp_directory_path() / ("wavecam_test_tracer_log_" + std::to_string(::getpid()));
    const int status = std::system((command + " > '" + log.string() + "' 2>&1").c_str());
    std::ifstream in(log);
    output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    fs::remove(log);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct Exr {
    int width = 0, height = 0;
    std::vector<float> r, g, b, z;
    OIIO::ImageSpec spec;
};

// Reads R, G, B and Z by name as float.
Exr read_exr(const std::string& path) {
    Exr e;
    auto in = OIIO::ImageInput::open(path);
    if (!in) return e;
    e.spec = in->spec();
    e.width = e.spec.width;
    e.height = e.spec.height;
    std::vector<float> all(static_cast<std::size_t>(e.width) * e.height * e.spec.nchannels);
    in->read_image(0, 0, 0, e.spec.nchannels, OIIO::TypeDesc::FLOAT, all.data());
    auto channel = [&](const char* name) {
        std::vector<float> out;
        const int c = e.spec.channelindex(name);
        if (c < 0) return out;
        for (std::size_t p = 0; p < static_cast<std::size_t>(e.width) * e.height; ++p)
            out.push_back(all[p * e.spec.nchannels + c]);
        return out;
    };
    e.r = channel("R"), e.g = channel("G"), e.b = channel("B"), e.z = channel("Z");
    return e;
}

std::array<double, 3> triple(const toml::node_view<const toml::node>& v) {
    return {v[0].value<double>().value(), v[1].value<double>().value(), v[2].value<double>().value()};
}

// The small scene's numbers, read straight from small.toml (not through the tracer's loader).
struct SmallScene {
    std::array<double, 3> position, look_at, up, plane_point, plane_normal, centre;
    double fov_deg, radius;
    int width, height;
};

SmallScene read_small_scene() {
    const toml::table t = toml::parse_file(kScenes + "/small.toml");
    SmallScene s;
    const toml::node_view<const toml::node> cam = t["camera"];
    s.position = triple(cam["position"]);
    s.look_at = triple(cam["look_at"]);
    s.up = triple(cam["up"]);
    s.fov_deg = cam["fov"].value<double>().value();
    s.width = cam["width"].value<int>().value();
    s.height = cam["height"].value<int>().value();
    const toml::node_view<const toml::node> objects = t["object"];
    s.plane_point = triple(objects[0]["point"]);
    s.plane_normal = triple(objects[0]["normal"]);
    s.centre = triple(objects[1]["center"]);
    s.radius = objects[1]["radius"].value<double>().value();
    return s;
}

// Pixel (i, j)'s centre ray from the convention alone: dir = D + x R + y U,
// x = (i + 0.5)/W - 0.5, y = 0.5 - (j + 0.5)/H, |R| = 2 tan(fov/2), |U| = |R| H/W,
// R = D x up. Its D component is 1, so along it planar depth = ray parameter.
using A3 = std::array<double, 3>;
A3 sub(A3 a, A3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dotp(A3 a, A3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
A3 unit(A3 a) {
    const double l = std::sqrt(dotp(a, a));
    return {a[0] / l, a[1] / l, a[2] / l};
}
A3 crossp(A3 a, A3 b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }

A3 pixel_ray(const SmallScene& s, int i, int j) {
    const A3 d = unit(sub(s.look_at, s.position));
    const A3 r = unit(crossp(d, s.up));
    const A3 u = crossp(r, d);
    const double rl = 2 * std::tan(s.fov_deg * M_PI / 360), ul = rl * s.height / s.width;
    const double x = (i + 0.5) / s.width - 0.5, y = 0.5 - (j + 0.5) / s.height;
    return {d[0] + x * rl * r[0] + y * ul * u[0], d[1] + x * rl * r[1] + y * ul * u[1], d[2] + x * rl * r[2] + y * ul * u[2]};
}

// Ray-plane: (o + t dir - p).n = 0; infinity when missed.
double plane_depth(const SmallScene& s, int i, int j) {
    const A3 dir = pixel_ray(s, i, j);
    const double t = dotp(sub(s.plane_point, s.position), s.plane_normal) / dotp(dir, s.plane_normal);
    return t > 0 ? t : INFINITY;
}

// Ray-sphere: |o + t dir - c|^2 = r^2, the nearer root; infinity when missed.
double sphere_depth(const SmallScene& s, int i, int j) {
    const A3 dir = pixel_ray(s, i, j), oc = sub(s.position, s.centre);
    const double a = dotp(dir, dir), b = dotp(dir, oc), c = dotp(oc, oc) - s.radius * s.radius;
    const double disc = b * b - a * c;
    const double t = disc >= 0 ? (-b - std::sqrt(disc)) / a : -1;
    return t > 0 ? t : INFINITY;
}

enum class Seen { Sky, Plane, Sphere };

// What pixel (i, j)'s centre ray hits first, and at which planar depth.
Seen analytic_depth(const SmallScene& s, int i, int j, double& depth) {
    const double plane = plane_depth(s, i, j), sphere = sphere_depth(s, i, j);
    depth = std::min(plane, sphere);
    if (std::isinf(depth)) return Seen::Sky;
    return sphere < plane ? Seen::Sphere : Seen::Plane;
}

// What a rendered depth shows at (i, j): sky at 1e10, the sphere where it is nearer than
// the plane would be.
Seen classify(const SmallScene& s, float z, int i, int j) {
    if (z >= 1e9f) return Seen::Sky;
    return z < 0.99 * plane_depth(s, i, j) ? Seen::Sphere : Seen::Plane;
}

}  // namespace

// Lengths go through core's unit parser (tested in tests/core/test_units.cpp); the tracer adds
// only that they be positive, and counts at most 65536.
TEST(TracerCommandLine, LengthsNeedAUnitAndArePositive) {
    auto parse = [](std::vector<std::string> flags) {
        flags.insert(flags.begin(), {"scene.toml", "out.exr"});
        return parse_command_line(flags);
    };
    const Result<TraceOptions> ok = parse({"--pinhole-diameter", "0.5mm", "--film-distance", "50mm", "--width", "64"});
    ASSERT_TRUE(ok.ok()) << ok.error;
    EXPECT_DOUBLE_EQ(ok.value.pinhole.diameter, 0.5e-3);
    EXPECT_DOUBLE_EQ(ok.value.pinhole.film_distance, 0.05);
    EXPECT_EQ(ok.value.width, 64);
    EXPECT_EQ(ok.value.pinhole_text, "0.5mm");
    struct Case {
        std::vector<std::string> flags;
        std::string expect;
    } cases[] = {
        {{"--pinhole-diameter", "0.5", "--film-distance", "50mm"}, "--pinhole-diameter: expected a length with a unit"},
        {{"--pinhole-diameter", "0.5in", "--film-distance", "50mm"}, "--pinhole-diameter: expected a length"},
        {{"--pinhole-diameter", "-1mm", "--film-distance", "50mm"}, "--pinhole-diameter: expected a positive length"},
        {{"--pinhole-diameter", "0.5mm"}, "go together"},
        {{"--width", "0"}, "--width: expected a whole number from 1 to 65536"},
        {{"--samples", "100000"}, "--samples: expected a whole number from 1 to 65536"},
        {{"--height", "12px"}, "--height: expected a whole number from 1 to 65536"},
    };
    for (const Case& c : cases) {
        const Result<TraceOptions> r = parse(c.flags);
        EXPECT_FALSE(r.ok()) << c.expect;
        EXPECT_NE(r.error.find(c.expect), std::string::npos) << r.error;
    }
}

TEST(TracerCamera, MapsKnownPointsToExpectedPixels) {
    // Looking down -z from the origin, fov 90: |R| = 2, W x H = 200 x 100 so |U| = 1.
    const Camera cam(CameraSettings{{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 90, 200, 100});
    auto expect_pixel = [&](Vec3 p, double px, double py) {
        const PixelPoint q = cam.project(p);
        EXPECT_NEAR(q.px, px, 1e-9) << p.x << "," << p.y << "," << p.z;
        EXPECT_NEAR(q.py, py, 1e-9) << p.x << "," << p.y << "," << p.z;
    };
    expect_pixel({0, 0, -5}, 100, 50);       // on the axis: image centre
    expect_pixel({1, 0, -1}, 200, 50);       // 45 deg right: right edge (x = +1/2 of |R| = 2)
    expect_pixel({-2, 0, -2}, 0, 50);        // 45 deg left: left edge
    expect_pixel({0, 0.5, -1}, 100, 0);      // y = 0.5 of |U| = 1 up: top edge (row 0)
    expect_pixel({0.5, -0.25, -1}, 150, 75); // quarter right, quarter down
    // The centre of pixel (0, 0) lies along D + x R + y U with x = 0.5/200 - 0.5, y = 0.5 - 0.5/100.
    const Vec3 d = cam.direction({0.5, 0.5});
    EXPECT_NEAR(d.x, 2 * (0.5 / 200 - 0.5), 1e-12);
    EXPECT_NEAR(d.y, 1 * (0.5 - 0.5 / 100), 1e-12);
    EXPECT_NEAR(d.z, -1, 1e-12);
    // A general camera: project inverts direction.
    const Camera tilted(CameraSettings{{1, 2, 3}, {-2, 0.5, -4}, {0.1, 1, 0}, 70, 64, 48});
    const Vec3 p = tilted.position() + tilted.direction({10.25, 40.5}) * 7.5;
    EXPECT_NEAR(tilted.project(p).px, 10.25, 1e-9);
    EXPECT_NEAR(tilted.project(p).py, 40.5, 1e-9);
    EXPECT_NEAR(tilted.planar_depth(p), 7.5, 1e-9);
}

TEST(TracerCamera, WorldToCameraPutsPointsInFrontAtPositiveZ) {
    const Camera cam(CameraSettings{{1, 2, 3}, {1, 2, -7}, {0, 1, 0}, 60, 64, 64});
    const auto m = cam.world_to_camera();
    const double p[4] = {2, 4, -7, 1};  // 10 m ahead, 1 right, 2 up
    double q[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 4; ++r) q[c] += p[r] * m[r * 4 + c];
    EXPECT_NEAR(q[0], 1, 1e-5);
    EXPECT_NEAR(q[1], 2, 1e-5);
    EXPECT_NEAR(q[2], 10, 1e-5);
}

TEST(TracerSubdivision, CatmullClarkFaceCounts) {
    // Unit cube: 8 vertices, 6 quads.
    PolygonMesh cube;
    for (int k = 0; k < 8; ++k) cube.positions.push_back({double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)});
    cube.face_sizes = {4, 4, 4, 4, 4, 4};
    cube.indices = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
    for (int level = 1; level <= 4; ++level) {
        const Result<RefinedSurface> r = catmull_clark(cube, level);
        ASSERT_TRUE(r.ok()) << r.error;
        EXPECT_EQ(r.value.quads.face_sizes.size(), 6u << (2 * level)) << "level " << level;  // 6 * 4^level
        for (int size : r.value.quads.face_sizes) EXPECT_EQ(size, 4);
        for (const Vec3& n : r.value.normals) EXPECT_NEAR(length(n), 1, 1e-6);
    }
    // One step: vertices = V + E + F = 8 + 12 + 6.
    EXPECT_EQ(catmull_clark(cube, 1).value.quads.positions.size(), 26u);
    // A tetrahedron: 4 triangles become 3 quads each, then x4 per level.
    PolygonMesh tet;
    tet.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    tet.face_sizes = {3, 3, 3, 3};
    tet.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    EXPECT_EQ(catmull_clark(tet, 1).value.quads.face_sizes.size(), 12u);
    EXPECT_EQ(catmull_clark(tet, 2).value.quads.face_sizes.size(), 48u);
    // The limit surface of a closed cube cage lies strictly inside the cage.
    const Result<RefinedSurface> level3 = catmull_clark(cube, 3);
    for (const Vec3& p : level3.value.quads.positions) {
        EXPECT_GT(p.x, 0);
        EXPECT_LT(p.x, 1);
    }
    EXPECT_FALSE(catmull_clark(cube, 0).ok());
}

TEST(TracerFinitePinhole, EdgeRayMeetsThePointAtTheBlurDiscRim) {
    // A point at planar depth z images into a disc of diameter d (1 + f/z) on the film; the
    // ray from the disc's rim through the opposite edge of the pinhole passes through it.
    const Camera cam(CameraSettings{{0, 1, 0}, {0, 1, -1}, {0, 1, 0}, 60, 256, 256});
    const FinitePinhole pinhole{0.5e-3, 50e-3};
    const double z = 0.4;
    const Vec3 point = cam.position() + cam.direction({100.3, 77.7}) * z;
    const double radius_px = blur_disc_pixels(cam, pinhole, z) / 2;
    // d (1 + f/z) / (2 f tan(30 deg) / 256)
    EXPECT_NEAR(2 * radius_px, 0.5e-3 * (1 + 50e-3 / z) / (2 * 50e-3 * std::tan(M_PI / 6) / 256), 1e-12);
    // Disc sample (1, 0.5) is the pinhole point +R d/2; its ray comes from the film point
    // radius_px to the left of the image of the point.
    const PixelPoint image = cam.project(point);
    const Ray ray = pinhole_ray(cam, pinhole, {image.px - radius_px, image.py}, 1.0, 0.5);
    EXPECT_NEAR(length(ray.origin - (cam.position() + cam.right_unit() * 0.25e-3)), 0, 1e-15);
    const Vec3 at_depth = ray.origin + ray.direction * z;  // D component of direction is 1
    EXPECT_NEAR(length(at_depth - point), 0, 1e-12);
    // The ideal pinhole's ray is the chief ray.
    const Ray chief = pinhole_ray(cam, FinitePinhole{}, image, 0.3, 0.8);
    EXPECT_NEAR(length(chief.origin + chief.direction * z - point), 0, 1e-12);
}

TEST(TracerRender, PlaneAndSphereDepthsMatchAnalyticIntersections) {
    const fs::path dir = scratch_dir("depth");
    const std::string out = (dir / "small.exr").string();
    std::string log;
    ASSERT_EQ(run("'" + kTrace + "' '" + kScenes + "/small.toml' '" + out + "' --samples 1", log), 0) << log;
    const Exr e = read_exr(out);
    const SmallScene s = read_small_scene();
    ASSERT_EQ(e.width, s.width);
    ASSERT_EQ(e.height, s.height);
    ASSERT_EQ(e.z.size(), static_cast<std::size_t>(s.width) * s.height);
    int counts[3] = {0, 0, 0};  // sky, plane, sphere
    double worst = 0;
    for (int j = 0; j < s.height; ++j)
        for (int i = 0; i < s.width; ++i) {
            double expected;
            const Seen seen = analytic_depth(s, i, j, expected);
            const float z = e.z[static_cast<std::size_t>(j) * s.width + i];
            ++counts[static_cast<int>(seen)];
            if (seen == Seen::Sky) {
                EXPECT_EQ(z, 1e10f) << "sky at " << i << "," << j;
            } else {
                worst = std::max(worst, std::abs(z - expected) / expected);
                EXPECT_NEAR(z, expected, 1e-4 * expected)
                    << (seen == Seen::Sphere ? "sphere" : "plane") << " at " << i << "," << j;
            }
        }
    // Header: what wavecam reads.
    EXPECT_FLOAT_EQ(e.spec.get_float_attribute("wavecam.fov"), static_cast<float>(s.fov_deg));
    EXPECT_EQ(e.spec.get_string_attribute("wavecam.depth"), "planar");
    EXPECT_EQ(e.spec.get_string_attribute("wavecam.scene"), "small.toml");
    EXPECT_NE(e.spec.find_attribute("worldToCamera", OIIO::TypeDesc::TypeMatrix44), nullptr);
    EXPECT_EQ(e.spec.format, OIIO::TypeDesc::FLOAT);
    fs::remove_all(dir);
}

TEST(TracerRender, FinitePinholeRendersAndRecordsItself) {
    const fs::path dir = scratch_dir("pinhole");
    const std::string out = (dir / "blur.exr").string();
    std::string log;
    ASSERT_EQ(run("'" + kTrace + "' '" + kScenes + "/small.toml' '" + out +
                      "' --samples 4 --pinhole-diameter 0.5mm --film-distance 50mm", log), 0) << log;
    const Exr e = read_exr(out);
    EXPECT_EQ(e.spec.get_string_attribute("wavecam.ray-pinhole"), "0.5mm");
    EXPECT_EQ(e.spec.get_string_attribute("wavecam.ray-film-distance"), "50mm");
    EXPECT_EQ(run("'" + kTrace + "' '" + kScenes + "/small.toml' '" + out + "' --pinhole-diameter 0.5 --film-distance 50mm", log), 1);
    EXPECT_NE(log.find("--pinhole-diameter: expected a length with a unit"), std::string::npos) << log;
    fs::remove_all(dir);
}

// Every bad input: exit status 1, one line on stderr naming the file and the key, no
// output file and nothing left beside it.
TEST(TracerRender, BadSceneFilesFailClearlyWithoutOutput) {
    const fs::path dir = scratch_dir("bad");
    const std::string camera =
        "[camera]\nposition = [0, 1, 5]\nlook_at = [0, 1, 0]\nfov = 50\nwidth = 8\nheight = 8\n"
        "[sky]\ncolor = [1, 1, 1]\n";
    const std::string sphere = "[[object]]\ntype = \"sphere\"\ncenter = [0, 1, 0]\nradius = 1\n";
    struct Case {
        const char* name;
        std::string text;
        std::string expected;  // in the message, after the file name
    };
    const Case cases[] = {
        {"unknown_key", camera + sphere + "colour = [1, 0, 0]\n", "[[object]] 1 (sphere): key 'colour': unknown key"},
        {"syntax", camera + "[[object]\n", ":9:"},
        {"missing_obj", camera + "[[object]]\ntype = \"mesh\"\nobj = \"nowhere.obj\"\n", "nowhere.obj: cannot open"},
        {"bad_type", camera + sphere + "radius = \"big\"\n", ""},
        {"wrong_value", camera + "[[object]]\ntype = \"sphere\"\ncenter = [0, 1]\nradius = 1\n",
         "key 'center': expected [x, y, z]"},
        {"missing_key", "[camera]\nposition = [0, 1, 5]\nlook_at = [0, 1, 0]\nwidth = 8\nheight = 8\n[sky]\ncolor = 1\n" + sphere,
         "[camera]: key 'fov': missing"},
        {"bad_glyph", camera + sphere + "texture = { type = \"text\", text = \"A#B\" }\n", "key 'text': no glyph for '#'"},
    };
    for (const Case& c : cases) {
        const fs::path scene = dir / (std::string(c.name) + ".toml");
        std::ofstream(scene) << c.text;
        const fs::path out = dir / (std::string(c.name) + ".exr");
        std::string log;
        EXPECT_EQ(run("'" + kTrace + "' '" + scene.string() + "' '" + out.string() + "'", log), 1) << c.name;
        EXPECT_EQ(log.rfind("wavecam-trace: " + scene.string(), 0), 0u) << c.name << ": " << log;
        EXPECT_NE(log.find(c.expected), std::string::npos) << c.name << ": " << log;
        EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << c.name << ": " << log;
        EXPECT_FALSE(fs::exists(out)) << c.name;
    }
    std::string log;
    EXPECT_EQ(run("'" + kTrace + "' '" + (dir / "absent.toml").string() + "' '" + (dir / "x.exr").string() + "'", log), 1);
    EXPECT_NE(log.find("absent.toml: no such scene file"), std::string::npos) << log;
    // An output that cannot be written leaves nothing behind either.
    EXPECT_EQ(run("'" + kTrace + "' '" + kScenes + "/small.toml' '" + (dir / "no_dir" / "x.exr").string() + "'", log), 1);
    EXPECT_NE(log.find("no_dir/x.exr: cannot write"), std::string::npos) << log;
    std::size_t left = 0;
    for (const auto& entry : fs::directory_iterator(dir)) left += entry.path().extension() != ".toml";
    EXPECT_EQ(left, 0u) << "files left beside the outputs";
    fs::remove_all(dir);
}

namespace {
struct Centroid {
    double x = 0, y = 0;
    int count = 0;
};
Centroid sphere_centroid(const SmallScene& s, const Exr& e) {
    Centroid c;
    for (int j = 0; j < s.height; ++j)
        for (int i = 0; i < s.width; ++i)
            if (classify(s, e.z[static_cast<std::size_t>(j) * s.width + i], i, j) == Seen::Sphere) {
                c.x += i + 0.5, c.y += j + 0.5, ++c.count;
            }
    c.x /= c.count, c.y /= c.count;
    return c;
}
}  // namespace

// The camera convention matches POV-Ray's: the small scene rendered by both puts the
// sphere's silhouette and every depth edge on the same pixels, and the depths agree within
// what render_pov.sh's fog depth pass can resolve. It reads d = -D ln(1 - diff) from
// half-float renders (relative rounding <= 2^-11 of a value <= 1 - t, t = exp(-u), u = d/D),
// so |delta d| / d <= 2^-11 (e^u - 1) / u; each pixel takes the fog distance (ratio 4 apart)
// with the least e^u / u, which keeps u <= 1.85: bound 2^-11 * 2.85.
constexpr double kFogDepthBound = 0x1p-11 * 2.85;
TEST(TracerPovRay, SmallSceneCameraAndDepthMatch) {
    std::string log;
    if (run("command -v povray", log) != 0) GTEST_SKIP() << "povray is not installed: POV-Ray comparison skipped";
    ASSERT_EQ(run("command -v oiiotool", log), 0) << "render_pov.sh needs oiiotool";
    const fs::path dir = scratch_dir("pov");
    const std::string pov = (dir / "pov.exr").string(), traced = (dir / "traced.exr").string();
    ASSERT_EQ(run("'" + std::string(WAVECAM_TEST_SCENES_DIR) + "/pov/render_pov.sh' small '" + pov + "' --width 64 --height 48", log), 0) << log;
    ASSERT_EQ(run("'" + kTrace + "' '" + kScenes + "/small.toml' '" + traced + "' --samples 1", log), 0) << log;
    const Exr p = read_exr(pov), t = read_exr(traced);
    const SmallScene s = read_small_scene();
    ASSERT_EQ(p.width, s.width);
    ASSERT_EQ(p.height, s.height);
    ASSERT_EQ(p.z.size(), t.z.size());
    EXPECT_FLOAT_EQ(p.spec.get_float_attribute("wavecam.fov"), t.spec.get_float_attribute("wavecam.fov"));
    EXPECT_EQ(p.spec.get_string_attribute("wavecam.depth"), "planar");
    const OIIO::ParamValue* pm = p.spec.find_attribute("worldToCamera", OIIO::TypeDesc::TypeMatrix44);
    const OIIO::ParamValue* tm = t.spec.find_attribute("worldToCamera", OIIO::TypeDesc::TypeMatrix44);
    ASSERT_TRUE(pm && tm);
    for (int k = 0; k < 16; ++k)
        EXPECT_NEAR(static_cast<const float*>(pm->data())[k], static_cast<const float*>(tm->data())[k], 1e-6) << k;

    // Misalignment 1: the sphere silhouette's centroid.
    const Centroid cp = sphere_centroid(s, p), ct = sphere_centroid(s, t);
    const double shift = std::hypot(cp.x - ct.x, cp.y - ct.y);
    // Misalignment 2: depth edges (sky/ground/sphere boundaries) per row and column: the
    // number of pixels whose class differs.
    int differing = 0, compared = 0;
    double worst = 0;
    auto at = [&](int i, int j) { return static_cast<std::size_t>(j) * s.width + i; };
    for (int j = 0; j < s.height; ++j)
        for (int i = 0; i < s.width; ++i) {
            const Seen a = classify(s, p.z[at(i, j)], i, j), b = classify(s, t.z[at(i, j)], i, j);
            differing += a != b;
            // Depths away from edges: both renders see the same thing in the 3x3 block.
            bool interior = a == b && a != Seen::Sky;
            for (int dj = -1; dj <= 1 && interior; ++dj)
                for (int di = -1; di <= 1 && interior; ++di) {
                    const int ii = std::clamp(i + di, 0, s.width - 1), jj = std::clamp(j + dj, 0, s.height - 1);
                    interior = classify(s, p.z[at(ii, jj)], ii, jj) == a && classify(s, t.z[at(ii, jj)], ii, jj) == a;
                }
            if (!interior) continue;
            ++compared;
            const double rel = std::abs(p.z[at(i, j)] - t.z[at(i, j)]) / t.z[at(i, j)];
            worst = std::max(worst, rel);
            EXPECT_LE(rel, kFogDepthBound) << "depth at " << i << "," << j << ": POV-Ray " << p.z[at(i, j)] << ", traced "
                                    << t.z[at(i, j)];
        }
    // Misalignment 3: edge positions. The horizon (first non-sky row) in every column and
    // the sphere's left and right silhouette in every row.
    int worst_edge = 0;
    auto first = [&](const Exr& e, int count, auto&& pixel, Seen want, bool reverse) {
        for (int k = 0; k < count; ++k) {
            const int kk = reverse ? count - 1 - k : k;
            const auto [i, j] = pixel(kk);
            if ((classify(s, e.z[at(i, j)], i, j) == want) != (want == Seen::Sky)) return kk;
        }
        return -1;
    };
    for (int i = 0; i < s.width; ++i) {
        auto down = [&](int j) { return std::pair<int, int>{i, j}; };
        worst_edge = std::max(worst_edge, std::abs(first(p, s.height, down, Seen::Sky, false) -
                                                   first(t, s.height, down, Seen::Sky, false)));
    }
    for (int j = 0; j < s.height; ++j) {
        auto across = [&](int i) { return std::pair<int, int>{i, j}; };
        for (bool from_right : {false, true})
            worst_edge = std::max(worst_edge, std::abs(first(p, s.width, across, Seen::Sphere, from_right) -
                                                       first(t, s.width, across, Seen::Sphere, from_right)));
    }
    std::printf("POV-Ray vs wavecam-trace: sphere centroid shift %.4f px (%+.4f, %+.4f; %d vs %d pixels), "
                "largest edge displacement %d px, %d pixels classified differently; worst relative depth "
                "difference %.2e over %d interior pixels (fog-pass bound %.2e)\n",
                shift, cp.x - ct.x, cp.y - ct.y, cp.count, ct.count, worst_edge, differing, worst, compared, kFogDepthBound);
    EXPECT_LE(shift, 1.0);
    EXPECT_LE(worst_edge, 1) << "depth edges disagree";
    EXPECT_GT(compared, s.width * s.height / 2);
    fs::remove_all(dir);
}
