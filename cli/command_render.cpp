// vfsd render SCENE.json --png OUT.png [--time t] [--size WxH] [--backend cpu|gpu]
//             [--wireframe] [--steps N] [--force] [--view SIDE] [--up y|z] [--zoom Z] [--target X,Y,Z]
//
// Renders the scene headless (OSMesa, or EGL in a build with VFSD_HEADLESS_GL=egl)
// as the apps show it: s from blue (0) to red (1), the region borders, the curve,
// a white sphere at the current time and a dark one at the scene's target time.
// --time integrates to t first, on the GPU (the default; its vertex texture is
// drawn without read-back) or on the CPU; the sphere tool always on the CPU.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "base/error.h"
#include "deform/quality.h"
#include "cli/commands.h"
#include "scene/framing.h"
#include "gpu/context.h"
#include "gpu/gpu_deformation.h"
#include "io/png.h"
#include "render/renderer.h"
#include "scene/prepared_scene.h"

namespace vfsd::cli {
namespace {

// "WxH" with both in [16, 8192].
void parse_size(const std::string& text, int& width, int& height) {
    char x = 0;
    char rest = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || (x != 'x' && x != 'X') ||
        width < 16 || height < 16 || width > 8192 || height > 8192)
        throw UsageError("--size expects WxH with both between 16 and 8192, e.g. 800x600");
}

// "X,Y,Z": three finite numbers.
Vec3 parse_point(const std::string& text) {
    double x = 0.0, y = 0.0, z = 0.0;
    char rest = 0;
    if (std::sscanf(text.c_str(), "%lf,%lf,%lf%c", &x, &y, &z, &rest) != 3 || !std::isfinite(x) ||
        !std::isfinite(y) || !std::isfinite(z))
        throw UsageError("--target expects X,Y,Z, e.g. 0.5,0,1.2");
    return Vec3(x, y, z);
}

}  // namespace

int run_render(const Args& args) {
    args.expect({"png", "time", "size", "backend", "wireframe", "steps", "force", "view", "up", "zoom", "target"}, 1, 1);
    const std::string scene_path = args.positional(0, "scene file");
    if (!args.has("png") || args.get("png").empty()) throw UsageError("--png OUT.png is required");
    const std::string out = args.get("png");
    Scene scene = load_scene(scene_path);
    // The GPU deforms by the same steps as the CPU (docs/gpu.md), as `vfsd deform
    // --backend gpu` does.
    const std::string backend = args.get("backend", "gpu");
    if (backend != "cpu" && backend != "gpu") throw UsageError("--backend must be 'cpu' or 'gpu'");
    int width = 800, height = 600;
    if (args.has("size")) parse_size(args.get("size"), width, height);
    const double time = args.get_number("time", 0.0);
    const double zoom = args.get_number("zoom", 1.0);
    if (!(zoom > 0.0 && zoom <= 1e6)) throw UsageError("--zoom expects a number in (0, 1e6]: 2 shows half as much");
    if (!(time >= 0.0 && time <= 1.0)) throw UsageError("--time expects a number in [0, 1]");
    std::error_code ec;
    if (std::filesystem::exists(out, ec) && !args.has("force"))
        throw vfsd::InputError(out + ": already exists (pass --force to replace it)");
    if (args.has("steps")) {
        const double steps = args.get_number("steps", 0);
        if (steps < 1 || steps != static_cast<int>(steps)) throw UsageError("--steps expects a positive integer");
        scene.options.steps = static_cast<int>(steps);
    }
    const std::unique_ptr<gpu::Context> context = gpu::create_headless_context();
    const PreparedScene prepared = prepare_scene(scene);
    for (const std::string& w : prepared.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    const auto& start = prepared.file.mesh.positions;

    // The camera frames the whole deformation, so frames of one scene at any time line up.
    Camera camera = Camera::framing(deformation_frame_points(start, prepared.region.s, prepared.motion),
                                    double(width) / double(height));
    const std::string up = args.get("up", std::string(1, scene.up_axis));  // default: the scene's
    if (up != "y" && up != "z") throw UsageError("--up must be 'y' or 'z'");
    camera.up_axis = up_axis_named(up);
    try {
        camera.set_view(standard_view_named(args.get("view", "iso")));
    } catch (const vfsd::InputError& e) {
        throw UsageError(std::string("--view: ") + e.what());
    }
    if (args.has("target")) camera.target = parse_point(args.get("target"));
    camera.distance /= zoom;
    const render::Renderer renderer(prepared.file.mesh.triangles, prepared.motion);
    render::RenderOptions options;
    options.current_time = time;
    options.target_time = scene.target_time;
    options.wireframe = args.has("wireframe");

    Deformation deformation =
        backend == "gpu" && !prepared.region.sphere_tool
            ? gpu::make_gpu_deformation(start, prepared.rings, prepared.region, prepared.motion, scene.options)
            : prepared.start_deformation();
    deformation.advance(time);
    // The GPU's vertex texture is drawn as it is; the CPU's positions are uploaded.
    const std::optional<DeviceVertices> on_gpu = deformation.device_vertices();
    std::optional<gpu::Texture> uploaded;
    if (on_gpu)
        options.vertex_origin = on_gpu->origin;
    else
        uploaded = render::make_vertex_texture(deformation.positions(), prepared.region.s);
    // Folded triangles are drawn in magenta, as the editors draw them.
    const std::vector<std::uint32_t> folds =
        flipped_triangle_list(start, deformation.positions(), prepared.file.mesh.triangles);
    options.highlight = &folds;
    const std::vector<std::uint8_t> image =
        render::render_image(renderer, on_gpu ? *on_gpu->texture : *uploaded, camera, width, height, options);
    write_png(out, width, height, image);
    std::printf("%s: %dx%d, t = %g, %s (%s: %s), %zu folded triangles (magenta)\n", out.c_str(), width, height, time,
                backend.c_str(), context->kind().c_str(), context->renderer().c_str(), folds.size());
    return kExitOk;
}

}  // namespace vfsd::cli
