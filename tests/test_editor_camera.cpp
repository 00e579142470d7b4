// The editor's camera and picking: a pixel's ray meets what is drawn at that pixel,
// zoom keeps the point under the cursor, drags land under the cursor, and the
// session's picker agrees with the plain loop as the mesh deforms, a scripted
// orbit turns the camera.

#include <catch2/catch.hpp>

#include <glm/trigonometric.hpp>

#include "editor/frame_log.h"
#include "editor/picking.h"
#include "editor/script.h"
#include "editor/session.h"
#include "io/mesh_file.h"
#include "view/camera.h"

using namespace vfsd;
using namespace vfsd::editor;

namespace {

Camera framed(const TriangleMesh& mesh, const Viewport& viewport) {
    Camera camera;
    camera.frame(mesh.positions, viewport.aspect());
    return camera;
}

}  // namespace

TEST_CASE("Camera: project and ray are inverse", "[editor][camera]") {
    const TriangleMesh mesh = load_mesh("builtin:box");
    const Viewport viewport{800, 600};
    Camera camera = framed(mesh, viewport);
    camera.orbit(37.0, -12.0);
    for (const Vec3& p : {mesh.positions[0], mesh.positions[100], Vec3(0.1, 0.2, 0.3)}) {
        const glm::dvec3 pixel = camera.project(p, viewport);
        const Ray ray = camera.ray(pixel.x, pixel.y, viewport);
        // Distance from p to the ray.
        const Vec3 w = p - ray.origin;
        const double off = glm::length(w - glm::dot(w, ray.direction) * ray.direction);
        CHECK(off < 1e-9 * camera.distance);
    }
}

TEST_CASE("Picking: the ray through a vertex's pixel hits the surface at that vertex", "[editor][camera]") {
    const TriangleMesh mesh = load_mesh("builtin:sphere");
    const Viewport viewport{640, 480};
    const Camera camera = framed(mesh, viewport);
    // The vertices facing the eye are visible: the nearest one to it certainly is.
    std::size_t nearest = 0;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        if (glm::length(mesh.positions[v] - camera.eye()) < glm::length(mesh.positions[nearest] - camera.eye()))
            nearest = v;
    const glm::dvec3 pixel = camera.project(mesh.positions[nearest], viewport);
    const auto hit = pick_surface(camera.ray(pixel.x, pixel.y, viewport), mesh.positions, mesh.triangles);
    REQUIRE(hit);
    CHECK(hit->nearest_vertex == nearest);
    CHECK(glm::length(hit->position - mesh.positions[nearest]) < 1e-9);
    // A pixel in a corner of the image misses the sphere.
    CHECK_FALSE(pick_surface(camera.ray(2, 2, viewport), mesh.positions, mesh.triangles));
}

TEST_CASE("Picking: the first surface along the ray wins", "[editor][camera]") {
    // Two parallel triangles; the ray from above meets the upper one first.
    const std::vector<Vec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
    const std::vector<Triangle> triangles = {{0, 1, 2}, {3, 4, 5}};
    const Ray ray{{0.2, 0.2, 5.0}, {0.0, 0.0, -1.0}};
    const auto hit = pick_surface(ray, positions, triangles);
    REQUIRE(hit);
    CHECK(hit->point.triangle == 1);
    CHECK(hit->distance == Approx(4.0));
    CHECK(hit->point.barycentric.x == Approx(0.6));
}

TEST_CASE("Camera: zoom keeps the point under the cursor", "[editor][camera]") {
    const Viewport viewport{800, 600};
    Camera camera;
    camera.target = Vec3(1.0, 2.0, 3.0);
    camera.distance = 10.0;
    const Ray before = camera.ray(600, 150, viewport);
    const Vec3 f = camera.forward();
    const Vec3 under = before.origin + (glm::dot(camera.target - before.origin, f) / glm::dot(before.direction, f)) * before.direction;
    camera.zoom(0.5, 600, 150, viewport);
    CHECK(camera.distance == Approx(5.0));
    const glm::dvec3 after = camera.project(under, viewport);
    CHECK(after.x == Approx(600.0).margin(1e-6));
    CHECK(after.y == Approx(150.0).margin(1e-6));
}

TEST_CASE("Camera: standard views and orbit", "[editor][camera]") {
    Camera camera;
    camera.set_view(StandardView::front);
    CHECK(glm::length(camera.forward() - Vec3(0.0, 1.0, 0.0)) < 1e-12);
    camera.set_view(StandardView::top);
    CHECK(camera.forward().z < -0.99);
    camera.set_view(StandardView::right);
    CHECK(glm::length(camera.forward() - Vec3(-1.0, 0.0, 0.0)) < 1e-12);
    const Vec3 target = camera.target;
    camera.orbit(100.0, 40.0);
    CHECK(camera.target == target);
    CHECK(glm::length(camera.eye() - target) == Approx(camera.distance));
}

TEST_CASE("Camera: every named view, with z or y up, centres the target with the up axis up on the screen",
          "[editor][camera][render]") {
    const Viewport viewport{400, 300};
    for (const char* up_name : {"z", "y"}) {
        const Vec3 up = up_name[0] == 'z' ? Vec3(0, 0, 1) : Vec3(0, 1, 0);
        for (const char* side : {"front", "back", "right", "left", "top", "bottom", "iso"}) {
            INFO(side << ", " << up_name << " up");
            Camera camera = Camera::framing({Vec3(1.0, -4.0, 3.0), Vec3(5.0, 0.0, 7.0)}, viewport.aspect());
            camera.up_axis = up_axis_named(up_name);
            camera.set_view(standard_view_named(side));
            const glm::dvec3 centre = camera.project(camera.target, viewport);
            CHECK(std::abs(centre.x - 199.5) < 1e-6);  // the middle pixel
            CHECK(std::abs(centre.y - 149.5) < 1e-6);
            CHECK(glm::length(camera.world_up() - up) < 1e-12);
            // The up axis points up on the screen (rows grow downward), except
            // when looking along it.
            if (std::abs(glm::dot(camera.forward(), up)) < 0.99)
                CHECK(camera.project(camera.target + 0.1 * camera.distance * up, viewport).y < centre.y - 1.0);
            // The mapping is a rotation: the same view with z up, turned.
            Camera z_up = camera;
            z_up.up_axis = UpAxis::z;
            const Vec3 d = z_up.eye() - z_up.target;
            const Vec3 turned = up_name[0] == 'z' ? d : Vec3(d.x, d.z, -d.y);
            CHECK(glm::length(camera.eye() - camera.target - turned) < 1e-9 * camera.distance);
        }
        Camera front;
        front.up_axis = up_axis_named(up_name);
        front.set_view(StandardView::front);
        CHECK(glm::length(-front.forward() - (up_name[0] == 'z' ? Vec3(0, -1, 0) : Vec3(0, 0, 1))) < 1e-12);
    }
    CHECK_THROWS_WITH(standard_view_named("side"), Catch::Contains("unknown view 'side'"));
    CHECK_THROWS_WITH(up_axis_named("x"), Catch::Contains("up axis"));
}

TEST_CASE("drag_point: screen-plane drags land under the cursor, axis drags move one coordinate", "[editor][camera]") {
    const Viewport viewport{800, 600};
    Camera camera;
    camera.distance = 6.0;
    const Vec3 from(0.3, -0.2, 0.5);
    const Vec3 moved = drag_point(from, 500, 200, camera, viewport);
    const glm::dvec3 pixel = camera.project(moved, viewport);
    CHECK(pixel.x == Approx(500.0).margin(1e-6));
    CHECK(pixel.y == Approx(200.0).margin(1e-6));
    CHECK(glm::dot(moved - from, camera.forward()) == Approx(0.0).margin(1e-12));
    const Vec3 along_z = drag_point(from, 400, 100, camera, viewport, 2);
    CHECK(along_z.x == from.x);
    CHECK(along_z.y == from.y);
    CHECK(along_z.z > from.z);  // dragging up the screen lifts it
}

namespace {

// The session's picker against the loop over all triangles at the session's positions, on a grid of pixels.
void check_session_picks(const EditorSession& session, const Camera& camera, const Viewport& viewport) {
    int hits = 0;
    for (int y = 0; y < viewport.height; y += 12)
        for (int x = 0; x < viewport.width; x += 12) {
            const Ray ray = camera.ray(x + 0.5, y + 0.5, viewport);
            const auto expected = pick_surface(ray, session.positions(), session.triangles());
            const auto got = session.pick_surface(ray);
            REQUIRE(got.has_value() == expected.has_value());
            if (!got) continue;
            ++hits;
            CHECK(got->point.triangle == expected->point.triangle);
            CHECK(got->point.barycentric == expected->point.barycentric);
            CHECK(got->distance == expected->distance);
            CHECK(got->position == expected->position);
            CHECK(got->nearest_vertex == expected->nearest_vertex);
        }
    CHECK(hits > 100);
}

}  // namespace

TEST_CASE("Picking: the session's picker follows the deformation, apply and undo", "[editor][camera]") {
    EditorSession session;
    session.open_mesh("builtin:bar:6");
    const Viewport viewport{480, 360};
    const Camera camera = framed(load_mesh("builtin:bar:6"), viewport);
    check_session_picks(session, camera, viewport);

    const std::uint64_t rest = session.positions_revision();
    session.set_target_time(0.6);
    while (session.moving()) session.update(10);
    CHECK(session.positions_revision() != rest);
    check_session_picks(session, camera, viewport);

    session.apply();
    check_session_picks(session, camera, viewport);
    REQUIRE(session.undo());
    check_session_picks(session, camera, viewport);
}

TEST_CASE("Picking: painting moves no vertex, so the positions' revision stays", "[editor][camera]") {
    EditorSession session;
    session.open_mesh("builtin:sphere");
    const std::uint64_t before = session.positions_revision();
    BrushSettings brush;
    brush.tool = BrushTool::paint_outer;
    session.brush(surface_point_at_vertex(session.triangles(), session.positions().size(), 0), brush);
    CHECK(session.positions_revision() == before);
}

namespace {

// Records what an orbit asks of the editor.
class OrbitHost final : public EditorHost {
public:
    std::optional<glm::dvec2> pointer;
    int frames_to_log = 0;
    void screenshot(const std::string&, bool) override {}
    void loaded() override {}
    void log(const std::string&) override {}
    void point_at(double x, double y) override { pointer = glm::dvec2(x, y); }
    void log_frame_times(int frames) override { frames_to_log = frames; }
};

}  // namespace

TEST_CASE("Scripts: an orbit turns the camera over its frames, a tool action picks the tool", "[editor][camera]") {
    EditorSession session;
    session.open_mesh("builtin:box");
    ToolController tools;
    Camera camera;
    const Camera start = camera;
    OrbitHost host;
    ScriptRunner script(parse_script("{\"action\": \"tool\", \"name\": \"inner\"}\n"
                                     "{\"action\": \"orbit\", \"degrees\": [90, -10], \"frames\": 4, \"pointer\": [300, 200]}\n",
                                     "orbit"));
    int frames = 0;
    EditorSettings settings;
    while (script.run_frame({session, tools, camera, settings, Viewport{640, 480}, host})) ++frames;
    REQUIRE_FALSE(script.failed());
    CHECK(frames == 4);  // four turning frames; the action ends on the fifth
    CHECK(tools.tool == Tool::paint_inner);
    CHECK(host.pointer == glm::dvec2(300, 200));
    CHECK(host.frames_to_log == 4);
    CHECK(camera.yaw - start.yaw == Approx(glm::radians(90.0)));
    CHECK(camera.pitch - start.pitch == Approx(glm::radians(-10.0)));
}

TEST_CASE("FrameLog: a line per frame, then the medians of each part and of the whole", "[editor][camera]") {
    FrameLog log;
    log.start(3);
    CHECK(log.add({1.0, 2.0, 3.0}).size() == 1);
    CHECK(log.add({5.0, 0.0, 0.0}) == std::vector<std::string>{"frame 2: app 5.00 ms, GL calls 0.00 ms, swap 0.00 ms, whole 5.00 ms"});
    const std::vector<std::string> last = log.add({2.0, 2.0, 2.0});
    REQUIRE(last.size() == 2);
    CHECK(last[1] == "frames: 3, median app 2.00 ms, GL calls 2.00 ms, swap 2.00 ms, whole 6.00 ms");
    CHECK_FALSE(log.active());
}
