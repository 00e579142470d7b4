// The shared renderer draws a scene from the vertex texture with s colour-coded:
// blue where s = 0, red where s = 1; and the CLI renders and deforms headless.
#include <sys/wait.h>

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "deform/quality.h"
#include "gpu/gl_objects.h"
#include "gpu/gpu_deformation.h"
#include "render/renderer.h"
#include "scene/framing.h"
#include "scene/prepared_scene.h"
#include "test_fold_support.h"
#include "test_gpu_support.h"

using namespace vfsd;

namespace {

const std::string kScene = std::string(VFSD_SOURCE_DIR) + "/assets/scenes/fig04-box-bend.json";

struct PixelCounts {
    int blue = 0, red = 0, background = 0;
};

PixelCounts count_pixels(const std::vector<std::uint8_t>& rgba) {
    PixelCounts c;
    for (std::size_t i = 0; i + 3 < rgba.size(); i += 4) {
        const int r = rgba[i], g = rgba[i + 1], b = rgba[i + 2];
        if (b > 120 && b > r + 60 && b > g + 40) ++c.blue;
        if (r > 120 && r > b + 60 && r > g + 60) ++c.red;
        if (r > 230 && g > 230 && b > 230) ++c.background;
    }
    return c;
}

}  // namespace

TEST_CASE("Rendered scene shows s = 0 in blue and s = 1 in red", "[gpu][render]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    Scene scene = load_scene(kScene);
    scene.options.steps = 20;
    scene.options = paper_steps(scene.options);
    const PreparedScene prepared = prepare_scene(scene);
    const auto& start = prepared.file.mesh.positions;
    const Camera camera = Camera::framing(deformation_frame_points(start, prepared.region.s, prepared.motion), 160.0 / 120);
    const render::Renderer renderer(prepared.file.mesh.triangles, prepared.motion);
    Deformation deformation = gpu::make_gpu_deformation(start, prepared.rings, prepared.region, prepared.motion, scene.options);
    for (double t : {0.0, 1.0}) {
        deformation.advance(t);
        render::RenderOptions options;
        options.current_time = t;
        options.vertex_origin = deformation.device_vertices()->origin;
        const std::vector<std::uint8_t> image =
            render::render_image(renderer, *deformation.device_vertices()->texture, camera, 160, 120, options);
        REQUIRE(image.size() == 160u * 120u * 4u);
        const PixelCounts c = count_pixels(image);
        INFO("t = " << t << ": " << c.blue << " blue, " << c.red << " red, " << c.background << " background pixels");
        CHECK(c.blue > 200);
        CHECK(c.red > 50);
        CHECK(c.background > 160 * 120 / 3);
    }
}

TEST_CASE("Folded triangles are drawn in magenta when asked for", "[gpu][render]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    const PreparedScene prepared = prepare_scene(test::folding_box_scene());
    Deformation deformation = prepared.start_deformation();
    deformation.advance(1.0);
    const auto& triangles = prepared.file.mesh.triangles;
    const std::vector<std::uint32_t> folded =
        flipped_triangle_list(prepared.file.mesh.positions, deformation.positions(), triangles);
    REQUIRE(!folded.empty());
    const Camera camera = Camera::framing(
        deformation_frame_points(prepared.file.mesh.positions, prepared.region.s, prepared.motion), 320.0 / 240);
    const render::Renderer renderer(triangles, prepared.motion);
    const gpu::Texture vertices = render::make_vertex_texture(deformation.positions(), prepared.region.s);
    const auto magenta = [](const std::vector<std::uint8_t>& rgba) {
        int n = 0;
        for (std::size_t i = 0; i + 3 < rgba.size(); i += 4)
            n += rgba[i] > 200 && rgba[i + 1] < 80 && rgba[i + 2] > 190;
        return n;
    };
    render::RenderOptions options;
    options.current_time = 1.0;
    CHECK(magenta(render::render_image(renderer, vertices, camera, 320, 240, options)) == 0);
    options.highlight = &folded;
    const int shown = magenta(render::render_image(renderer, vertices, camera, 320, 240, options));
    INFO(folded.size() << " folded triangles, " << shown << " magenta pixels");
    CHECK(shown > 0);
}

TEST_CASE("vfsd render and vfsd deform --backend gpu run headless", "[gpu][render][cli]") {
    VFSD_REQUIRE_GPU_CONTEXT();
    const auto dir = std::filesystem::temp_directory_path() / "vfsd_test_gpu_cli";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string png = (dir / "scene.png").string(), mesh = (dir / "out.obj").string(),
                      report = (dir / "report.json").string();
    const std::string cli = std::string("'") + VFSD_CLI_PATH + "'";
    CHECK(std::system((cli + " render '" + kScene + "' --png '" + png + "' --time 0.5 --steps 20 --size 64x48 >/dev/null")
                          .c_str()) == 0);
    CHECK(std::filesystem::file_size(png) > 100);
    CHECK(std::system((cli + " render '" + kScene + "' --png '" + png + "' --size 10x10 2>/dev/null").c_str()) != 0);
    CHECK(std::system((cli + " deform '" + kScene + "' --out '" + mesh + "' --report '" + report +
                       "' --steps 20 --backend gpu >/dev/null")
                          .c_str()) == 0);
    std::ifstream in(report);
    const nlohmann::json json = nlohmann::json::parse(in);
    CHECK(json["backend"] == "gpu");
    CHECK(!json["gl_renderer"].get<std::string>().empty());
    CHECK(json["gl_context"] == vfsd::test::gpu_context()->kind());
    CHECK(json["steps"] == 20);
    // The GPU takes the default scheme's steps: its volume keeper holds the volume
    // (sec. 5's steps alone lose about 3 % on this scene).
    CHECK(json["volume_error_percent"].get<double>() < 0.01);
    std::filesystem::remove_all(dir);
}

TEST_CASE("vfsd render refuses an unknown view, a bad zoom or target with exit code 2", "[gpu][render][cli]") {
    const std::string scene = std::string(VFSD_SOURCE_DIR) + "/assets/scenes/fig04-box-bend.json";
    for (const char* bad : {"--view side", "--up x", "--zoom 0", "--zoom -1", "--target 1,2", "--target 1,2,nan"}) {
        const std::string command = std::string("'") + VFSD_CLI_PATH + "' render '" + scene +
                                    "' --png /nonexistent/never.png " + bad + " 2>/dev/null";
        const int status = std::system(command.c_str());
        INFO(bad);
        CHECK(WIFEXITED(status));
        CHECK(WEXITSTATUS(status) == 2);
    }
}
