// Meshes larger than the GPU's texture limits: the GPU path refuses them with one
// message that names the limit and the CPU path, and the editors then run the CPU
// path and say why. No GL context is needed: the limits come in as Capabilities.
#include <catch2/catch.hpp>

#include "editor/session.h"
#include "gpu/capabilities.h"
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
    editor::EditorSession session([](const PreparedScene& scene) -> std::unique_ptr<editor::LiveDeformation> {
        gpu::require_gpu_support(small_gpu(64), std::max(scene.file.mesh.vertex_count(), scene.rings.neighbours.size()));
        FAIL("the mesh should not fit");
        return nullptr;
    });
    session.open_mesh("builtin:bar");
    session.set_target_time(0.1);
    while (session.moving()) REQUIRE(session.update(50) > 0);
    CHECK(session.stats().backend == "cpu");
    CHECK(session.stats().backend_reason.find("texture rows") != std::string::npos);
    CHECK(session.positions() != session.base_positions());
}
