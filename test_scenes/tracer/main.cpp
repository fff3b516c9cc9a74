// wavecam-trace: renders a test scene to the EXR wavecam takes (see command_line.h).
#include <chrono>
#include <cstdio>
#include "camera.h"
#include "command_line.h"
#include "exr_output.h"
#include "render.h"
#include "scene_loader.h"
#include "trace_scene.h"

using namespace wavecam::trace;
using wavecam::Result;

namespace {
int fail(const std::string& message) {
    std::fprintf(stderr, "wavecam-trace: %s\n", message.c_str());
    return 1;
}
}  // namespace

int main(int argc, char** argv) {
    const Result<TraceOptions> parsed = parse_command_line({argv + 1, argv + argc});
    if (!parsed.ok()) return fail(parsed.error);
    const TraceOptions& opt = parsed.value;
    if (opt.help) {
        std::fputs(kUsage, stdout);
        return 0;
    }
    Result<Scene> loaded = load_scene(opt.scene_path);
    if (!loaded.ok()) return fail(loaded.error);
    Scene scene = std::move(loaded.value);
    if (opt.width) scene.camera.width = *opt.width;
    if (opt.height) scene.camera.height = *opt.height;
    const int samples = opt.samples.value_or(scene.samples_per_pixel);

    const auto start = std::chrono::steady_clock::now();
    Result<std::unique_ptr<TraceScene>> geometry = TraceScene::build(scene);
    if (!geometry.ok()) return fail(opt.scene_path + ": " + geometry.error);
    const Camera camera(scene.camera);
    const RenderedImage image = render(scene, *geometry.value, camera, opt.pinhole, samples);

    ExrHeader header{static_cast<float>(camera.fov_deg()), scene.name, camera.world_to_camera(), {}};
    if (opt.pinhole.diameter > 0) {
        header.extra = {{"wavecam.ray-pinhole", opt.pinhole_text}, {"wavecam.ray-film-distance", opt.film_distance_text}};
    }
    const Result<bool> written = write_exr(opt.output_path, image, header);
    if (!written.ok()) return fail(written.error);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("%s: %dx%d, %d samples/pixel, %.2f s\n", opt.output_path.c_str(), image.width, image.height, samples,
                seconds);
    return 0;
}
