// Meshes larger than the GPU's texture limits: the GPU path refuses them with one
// message that names the limit and the CPU path, and the editors then run the CPU
// path and say why. No GL context is needed: the limits come in as Capabilities.
#include <catch2/catch.hpp>

#include "editor/session.h"
#include "gpu/capabilities.h"
#include "gpu/gpu_deformation.h"
#include "gpu/gpu_error.h"
#include "scene/prepared_scene.h"

using namespace vfsd;

namespace {

// A context whose textures are at most `size` texels wide and high.
gpu::Capabilities small_gpu(int size) {
    gpu::Capabilities caps;
    caps.renderer = "tiny test GPU";
    caps.max_texture_size = size;
    caps.float_render_targets = true;
    return caps;
}

std::string refusal(const gpu::Capabilities& caps, std::size_t items) {
    try {
        gpu::require_gpu_support(caps, items);
    } catch (const gpu::GpuUnavailable& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("the GPU path takes what fits its textures and refuses the rest, naming the CPU path", "[gpu][robustness]") {
    const gpu::Capabilities caps = small_gpu(64);
    CHECK(refusal(caps, 64 * 64).empty());
    const std::string message = refusal(caps, 64 * 64 + 1);
    CHECK(message.find("4097") != std::string::npos);
    CHECK(message.find("maximum 64") != std::string::npos);
    CHECK(message.find("CPU path") != std::string::npos);
    CHECK(!refusal(small_gpu(32), 1).empty());  // below any usable size
    gpu::Capabilities no_float = small_gpu(4096);
    no_float.float_render_targets = false;
    CHECK(refusal(no_float, 1).find("EXT_color_buffer_float") != std::string::npos);
}

TEST_CASE("an editor whose GPU cannot hold the mesh deforms on the CPU and says why", "[gpu][robustness][editor]") {
    // The GPU factory checks the mesh against a 64 x 64 texture, as GpuPasses does
    // with the context's real limit; the built-in bar (9,730 vertices) does not fit.
    editor::EditorSession session([](const PreparedScene& scene) -> Deformation {
        gpu::require_gpu_support(small_gpu(64), std::max(scene.file.mesh.vertex_count(), scene.rings.neighbours.size()));
        FAIL("the mesh should not fit");
        throw std::logic_error("unreachable");
    });
    session.open_mesh("builtin:bar");
    session.set_target_time(0.1);
    while (session.moving()) REQUIRE(session.update(50) > 0);
    CHECK(session.stats().backend == "cpu");
    CHECK(session.stats().backend_reason.find("texture rows") != std::string::npos);
    CHECK(session.positions() != session.base_positions());
}

TEST_CASE("the GPU path refuses meshes too small or too large for float textures, naming the cause", "[gpu][robustness]") {
    // Checked before any GL call, so no context is needed.
    for (const double scale : {1e-30, 1e30}) {
        const Scene scene =
            parse_scene(nlohmann::json::parse(
                            R"({"mesh": "builtin:box:4", "curve": {"bezier": [[0,0,0.6],[0,0,0.8],[0,0,1],[0,0,1.2]]},
            "region": {"kind": "geodesic", "seed": [0, 0, 0.6], "g_min": 0.2, "g_max": 0.8},
            "stream_gauge": "paper", "keep_volume": false, "fold_repair": false})"),
                        "");
        const PreparedScene p = prepare_scene(scene);
        std::vector<Vec3> positions = p.file.mesh.positions;
        for (Vec3& x : positions) x *= scale;
        try {
            Deformation d = gpu::make_gpu_deformation(positions, p.rings, p.region, p.motion, scene.options);
            FAIL("the GPU took a mesh scaled by " << scale);
        } catch (const gpu::GpuUnavailable& e) {
            CHECK_THAT(e.what(), Catch::Contains(scale < 1 ? "coordinates too small" : "coordinates too large") &&
                                     Catch::Contains("--backend cpu"));
        }
    }
}

TEST_CASE("both shells run the CPU path on a software renderer unless asked, say why, and do not multisample there",
          "[gpu][robustness][editor]") {
    // No GL needed: the rule reads the capabilities only.
    gpu::Capabilities caps = small_gpu(8192);
    for (const char* hardware : {"NVIDIA GeForce RTX 4090/PCIe/SSE2", "ANGLE (AMD, Radeon RX 7900)", "Mali-G710"}) {
        caps.renderer = hardware;
        INFO(hardware);
        CHECK(gpu::software_renderer(hardware).empty());
        CHECK(gpu::cpu_path_reason(caps, "auto").empty());
        CHECK(gpu::cpu_path_reason(caps, "gpu").empty());
        CHECK(!gpu::cpu_path_reason(caps, "cpu").empty());
        CHECK(gpu::multisample_view(hardware));
        CHECK(!gpu::multisample_view(hardware, "off"));
    }
    const std::pair<const char*, const char*> software[] = {
        {"ANGLE (Google, Vulkan 1.3.0 (SwiftShader Device (Subzero)), SwiftShader driver)", "SwiftShader"},
        {"llvmpipe (LLVM 15.0.6, 256 bits)", "llvmpipe"},
        {"softpipe", "softpipe"},
        {"Microsoft Basic Render Driver (software)", "software"}};
    for (const auto& [renderer, name] : software) {
        caps.renderer = renderer;
        INFO(renderer);
        CHECK(gpu::software_renderer(renderer) == name);
        CHECK_THAT(gpu::cpu_path_reason(caps, "auto"), Catch::Contains(std::string("software renderer (") + name + ")"));
        CHECK(gpu::cpu_path_reason(caps, "gpu").empty());  // asked for: the GPU path anyway
        CHECK(!gpu::multisample_view(renderer));           // each sample shaded on the CPU
        CHECK(gpu::multisample_view(renderer, "on"));
    }
    caps.float_render_targets = false;  // what no GPU path can do without, asked for or not
    for (const char* requested : {"auto", "gpu"})
        CHECK_THAT(gpu::cpu_path_reason(caps, requested), Catch::Contains("EXT_color_buffer_float"));
}
