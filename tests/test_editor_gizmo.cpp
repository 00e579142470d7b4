// The handle gizmo (sec. 6.2): each part is hit where its 3D shape projects and
// nothing far from it; an axis drag moves the target along that axis only; a ring
// drag turns the target about that axis by the angle swept on screen
// (counter-clockwise seen from the axis's tip is positive); a drag is one undo
// step; the session it leaves deforms as `vfsd deform` of its saved scene does.

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <map>

#include <glm/trigonometric.hpp>

#include "editor/handle_gizmo.h"
#include "editor/picking.h"
#include "editor/script.h"
#include "editor/session.h"
#include "editor/tools.h"
#include "io/mesh_file.h"
#include "mesh/geometry.h"
#include "test_io_support.h"

using namespace vfsd;
using namespace vfsd::editor;

namespace {

const Viewport kViewport{800, 600};
constexpr GizmoPart kAxisParts[3] = {GizmoPart::axis_x, GizmoPart::axis_y, GizmoPart::axis_z};
constexpr GizmoPart kRingParts[3] = {GizmoPart::ring_x, GizmoPart::ring_y, GizmoPart::ring_z};

// A scene of assets/scenes open in the editor core (40 steps), framed with the
// handle's target when it has one.
struct OpenScene {
    EditorSession session;
    Camera camera;
    ToolController tools;

    explicit OpenScene(const std::string& name) {
        Scene scene = load_scene(VFSD_SOURCE_DIR "/assets/scenes/" + name);
        scene.options.steps = 40;
        session.open_scene(scene);
        std::vector<Vec3> points = session.base_positions();
        if (scene.motion.curve.is_handle) points.push_back(scene.motion.curve.to.position);
        camera.frame(points, kViewport.aspect());
        tools.adapt_to(session);
    }
    HandleFrame target() const { return session.curve().curve.to; }
    HandleGizmo gizmo() const { return HandleGizmo(target(), camera, kViewport); }
};

// Fig. 13's bar with its handle.
struct HandleScene : OpenScene {
    HandleScene() : OpenScene("fig13-bar-handle-bend.json") {}
};

// The axes the header promises: x = ŵ, y = m̂ × ŵ, z = m̂.
std::array<Vec3, 3> frame_axes(const HandleFrame& f) { return {f.binormal, glm::cross(f.normal, f.binormal), f.normal}; }

// Rodrigues: v turned by `radians` about the unit axis k.
Vec3 turned(const Vec3& v, const Vec3& k, double radians) {
    return v * std::cos(radians) + glm::cross(k, v) * std::sin(radians) + k * glm::dot(k, v) * (1.0 - std::cos(radians));
}

glm::dvec2 pixel(const Camera& camera, const Vec3& p) {
    const glm::dvec3 s = camera.project(p, kViewport);
    return {s.x, s.y};
}

// `p` turned about `c` by `degrees`, counter-clockwise as the screen shows it.
glm::dvec2 turned_on_screen(glm::dvec2 p, glm::dvec2 c, double degrees) {
    const double a = glm::radians(degrees);
    const glm::dvec2 d = p - c;
    return c + glm::dvec2(d.x * std::cos(a) + d.y * std::sin(a), -d.x * std::sin(a) + d.y * std::cos(a));
}

double screen_angle(glm::dvec2 p, glm::dvec2 c) { return std::atan2(-(p.y - c.y), p.x - c.x); }

// Pixels along every part, projected from the 3D geometry: axes from ĥ to
// ĥ + length·axis, rings of the radius about ĥ in the plane of the other two axes.
std::map<GizmoPart, std::vector<glm::dvec2>> part_pixels(const HandleGizmo& g, const HandleFrame& f, const Camera& c) {
    std::map<GizmoPart, std::vector<glm::dvec2>> out;
    const auto axes = frame_axes(f);
    out[GizmoPart::centre] = {pixel(c, f.position)};
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i <= 200; ++i) out[kAxisParts[k]].push_back(pixel(c, f.position + g.axis_length() * i / 200.0 * axes[k]));
        const Vec3 u = axes[(k + 1) % 3], v = axes[(k + 2) % 3];
        for (int i = 0; i < 720; ++i) {
            const double a = glm::radians(i / 2.0);
            out[kRingParts[k]].push_back(pixel(c, f.position + g.ring_radius() * (std::cos(a) * u + std::sin(a) * v)));
        }
    }
    return out;
}

// Distance in pixels from p to a part (the centre: to its disk's rim).
double distance(glm::dvec2 p, GizmoPart part, const std::map<GizmoPart, std::vector<glm::dvec2>>& pixels, double disk) {
    double best = 1e300;
    for (const glm::dvec2& q : pixels.at(part)) best = std::min(best, glm::length(p - q));
    return part == GizmoPart::centre ? std::max(0.0, best - disk) : best;
}

// Views of the bar's handle: the editors' framing, and two orbits about it.
std::vector<Camera> views(const Camera& framed) {
    Camera a = framed, b = framed;
    a.orbit(120.0, 40.0);
    b.orbit(-210.0, -55.0);
    return {framed, a, b};
}

// Calls check(camera, gizmo, start, axes, k) for every view and axis k of the scene's target.
template <class Check>
void for_each_view_and_axis(const HandleScene& h, Check check) {
    for (const Camera& camera : views(h.camera)) {
        const HandleFrame start = h.target();
        const HandleGizmo g(start, camera, kViewport);
        const auto axes = frame_axes(start);
        for (int k = 0; k < 3; ++k) {
            INFO("axis " << k);
            check(camera, g, start, axes, k);
        }
    }
}

void run_to_target(EditorSession& session) {
    while (session.moving()) session.update(10);
}

// What `vfsd deform` computes for a scene, through the library (CPU).
std::vector<Vec3> deform_scene(const Scene& scene) {
    Deformation deformation = prepare_scene(scene).start_deformation();
    deformation.advance(scene.target_time);
    return deformation.positions();
}

// Drags `part` through the tools as a pointer would: press on its grab point,
// then `steps` moves along `path(k)`, release.
template <class Path>
void pointer_drag(HandleScene& h, GizmoPart part, int steps, Path path) {
    const auto grab = h.gizmo().grab_point(part);
    REQUIRE(grab);
    h.tools.tool = Tool::navigate;
    REQUIRE(h.tools.press(h.session, h.camera, kViewport, grab->x, grab->y));
    REQUIRE(h.tools.highlighted_gizmo_part(h.session, h.camera, kViewport, grab->x, grab->y) == part);
    for (int k = 1; k <= steps; ++k) {
        const glm::dvec2 p = path(*grab, k);
        h.tools.drag(h.session, h.camera, kViewport, p.x, p.y);
    }
    h.tools.release(h.session);
    REQUIRE(h.tools.message.empty());
}

class QuietHost final : public EditorHost {
public:
    void screenshot(const std::string&, bool) override {}
    void loaded() override {}
    void log(const std::string&) override {}
};

}  // namespace

TEST_CASE("Handle gizmo: each part is hit where it projects, nothing far from the gizmo", "[editor][gizmo]") {
    HandleScene h;
    int view = 0;
    for (const Camera& camera : views(h.camera)) {
        INFO("view " << view++);
        const HandleGizmo g(h.target(), camera, kViewport);
        REQUIRE(g.visible());
        const auto pixels = part_pixels(g, h.target(), camera);
        const double disk = g.shapes().centre_radius;
        CHECK(g.hit(g.centre().x, g.centre().y) == GizmoPart::centre);
        CHECK(glm::length(g.centre() - pixel(camera, h.target().position)) < 1e-9);

        // Where a part projects and no other part comes within 10 pixels, it is hit;
        // every part has a point that picks it (an axis seen nearly end-on may
        // have little more than its tip clear of the rings).
        int clear = 0;
        for (const auto& [part, samples] : pixels) {
            if (part == GizmoPart::centre) continue;  // the axes start on it
            INFO("part " << gizmo_part_name(part));
            for (const glm::dvec2& p : samples) {
                double others = 1e300;
                for (const auto& [other, unused] : pixels)
                    if (other != part) others = std::min(others, distance(p, other, pixels, disk));
                if (others < 10.0) continue;
                ++clear;
                CHECK(g.hit(p.x, p.y) == part);
            }
            const auto grab = g.grab_point(part);
            REQUIRE(grab);
            CHECK(g.hit(grab->x, grab->y) == part);
            CHECK(distance(*grab, part, pixels, disk) < 1.0);
        }
        CHECK(clear > 500);
        // Across the whole view: far from every part nothing is hit, and a hit
        // lies within the pick distance of the part it names.
        int far = 0;
        for (int y = 0; y < kViewport.height; y += 7)
            for (int x = 0; x < kViewport.width; x += 7) {
                const glm::dvec2 p(x, y);
                double nearest = 1e300;
                for (const auto& [part, unused] : pixels) nearest = std::min(nearest, distance(p, part, pixels, disk));
                const GizmoPart hit = g.hit(x, y);
                if (nearest > 10.0) {
                    ++far;
                    CHECK(hit == GizmoPart::none);
                }
                if (hit != GizmoPart::none) CHECK(distance(p, hit, pixels, disk) < 8.0);
            }
        CHECK(far > 9000);
    }
}

TEST_CASE("Handle gizmo: an axis drag moves the target along that axis only", "[editor][gizmo]") {
    const HandleScene h;
    for_each_view_and_axis(h, [](const Camera& camera, const HandleGizmo& g, const HandleFrame& start,
                                 const std::array<Vec3, 3>& axes, int k) {
        const glm::dvec2 on_screen = pixel(camera, start.position + g.axis_length() * axes[k]) - g.centre();
        REQUIRE(glm::length(on_screen) > 30.0);
        const glm::dvec2 along = glm::normalize(on_screen), across(-along.y, along.x);
        const auto a = g.grab_point(kAxisParts[k]);
        REQUIRE(a);
        REQUIRE(g.hit(a->x, a->y) == kAxisParts[k]);

        // Toward the tip on screen: along +axis, and the axis point under the
        // pointer at the press stays under the pointer.
        const glm::dvec2 b = *a + 40.0 * along;
        const HandleFrame moved = g.drag(kAxisParts[k], *a, b);
        const Vec3 delta = moved.position - start.position;
        CHECK(glm::dot(delta, axes[k]) > 0.1 * g.axis_length());
        CHECK(glm::length(delta - glm::dot(delta, axes[k]) * axes[k]) < 1e-9 * glm::length(delta));
        CHECK(moved.normal == start.normal);
        CHECK(moved.binormal == start.binormal);
        const double s = *line_parameter_at_pixel(start.position, axes[k], a->x, a->y, camera, kViewport);
        CHECK(glm::length(pixel(camera, moved.position + s * axes[k]) - b) < 1e-6);

        // Across the axis on screen: hardly any motion.
        const HandleFrame sideways = g.drag(kAxisParts[k], *a, *a + 40.0 * across);
        CHECK(glm::length(sideways.position - start.position) < 0.25 * glm::length(delta));
    });
}

TEST_CASE("Handle gizmo: a ring drag turns the target by the swept angle about its axis", "[editor][gizmo]") {
    SECTION("seen from above: counter-clockwise on screen is positive about an axis toward the eye") {
        for (const double up : {1.0, -1.0}) {
            HandleFrame start;
            start.position = Vec3(0.3, -0.2, 0.5);
            start.normal = Vec3(0.0, 0.0, up);  // z axis: toward the eye, or away from it
            start.binormal = Vec3(1.0, 0.0, 0.0);
            Camera camera;
            camera.target = start.position;
            camera.distance = 5.0;
            camera.set_view(StandardView::top);
            const HandleGizmo g(start, camera, kViewport);
            const auto a = g.grab_point(GizmoPart::ring_z);
            REQUIRE(a);
            const HandleFrame turned_frame = g.drag(GizmoPart::ring_z, *a, turned_on_screen(*a, g.centre(), 30.0));
            // From above, x is right and y up on screen: the binormal turns from x toward y.
            const double c = std::cos(glm::radians(30.0)), s = std::sin(glm::radians(30.0));
            CHECK(glm::length(turned_frame.binormal - Vec3(c, s, 0.0)) < 1e-9);
            CHECK(glm::length(turned_frame.normal - start.normal) < 1e-12);
            CHECK(turned_frame.position == start.position);
            CHECK(g.swept_angle(GizmoPart::ring_z, *a, turned_on_screen(*a, g.centre(), 30.0)) ==
                  Approx(up * glm::radians(30.0)));
        }
    }
    SECTION("every ring of the bar's handle, from several views") {
        const HandleScene h;
        for_each_view_and_axis(h, [](const Camera& camera, const HandleGizmo& g, const HandleFrame& start,
                                     const std::array<Vec3, 3>& axes, int k) {
            const auto a = g.grab_point(kRingParts[k]);
            REQUIRE(a);
            const glm::dvec2 b = turned_on_screen(*a, g.centre(), 25.0);
            const HandleFrame next = g.drag(kRingParts[k], *a, b);
            const bool tip_toward_eye = glm::dot(axes[k], camera.eye() - start.position) > 0.0;
            const double angle = glm::radians(tip_toward_eye ? 25.0 : -25.0);
            CHECK(glm::length(next.normal - turned(start.normal, axes[k], angle)) < 1e-9);
            CHECK(glm::length(next.binormal - turned(start.binormal, axes[k], angle)) < 1e-9);
            CHECK(glm::length(frame_axes(next)[k] - axes[k]) < 1e-9);
            CHECK(next.position == start.position);
            CHECK(std::abs(glm::dot(next.normal, next.binormal)) < 1e-12);
            // The ring follows the pointer: its point under the press turns
            // counter-clockwise on screen too (for rings not seen edge-on).
            if (std::abs(glm::dot(axes[k], glm::normalize(camera.eye() - start.position))) < 0.5) return;
            const Vec3 u = axes[(k + 1) % 3], v = axes[(k + 2) % 3];
            const auto next_axes = frame_axes(next);
            double best = 1e300, phi = 0.0;
            for (int i = 0; i < 3600; ++i) {
                const double p = glm::radians(i / 10.0);
                const double d = glm::length(pixel(camera, start.position + g.ring_radius() * (std::cos(p) * u + std::sin(p) * v)) - *a);
                if (d < best) best = d, phi = p;
            }
            const Vec3 carried = start.position + g.ring_radius() * (std::cos(phi) * next_axes[(k + 1) % 3] +
                                                                     std::sin(phi) * next_axes[(k + 2) % 3]);
            const double moved = screen_angle(pixel(camera, carried), g.centre()) - screen_angle(*a, g.centre());
            CHECK(std::sin(moved) > 0.0);
        });
    }
}

TEST_CASE("Handle gizmo: a drag through the tools is one undo step", "[editor][gizmo]") {
    HandleScene h;
    const MotionSpec before = h.session.curve();
    const std::size_t steps_before = h.session.history().undo_count();

    // A quarter turn of the y ring in ten pointer moves.
    const glm::dvec2 centre = h.gizmo().centre();
    pointer_drag(h, GizmoPart::ring_y, 10, [&](glm::dvec2 grab, int k) { return turned_on_screen(grab, centre, 9.0 * k); });
    REQUIRE(h.session.history().undo_count() == steps_before + 1);
    CHECK(h.session.history().last()->label == "rotate handle");
    const MotionSpec after = h.session.curve();
    CHECK(after.curve.from.position == before.curve.from.position);
    CHECK(after.curve.from.normal == before.curve.from.normal);
    CHECK(std::abs(glm::dot(after.curve.to.normal, before.curve.to.normal)) < 1e-9);  // 90 degrees about y ⟂ m̂
    CHECK(glm::length(frame_axes(after.curve.to)[1] - frame_axes(before.curve.to)[1]) < 1e-9);

    // An axis drag: one more step.
    pointer_drag(h, GizmoPart::axis_z, 6, [](glm::dvec2 grab, int k) { return grab + glm::dvec2(0.0, -5.0 * k); });
    REQUIRE(h.session.history().undo_count() == steps_before + 2);
    CHECK(h.session.history().last()->label == "move handle");
    CHECK(h.session.curve().curve.to.position != after.curve.to.position);

    REQUIRE(h.session.undo());
    CHECK(h.session.curve() == after);
    REQUIRE(h.session.undo());
    CHECK(h.session.curve() == before);
    CHECK(h.session.control_points() == std::vector<Vec3>{before.curve.from.position, before.curve.to.position});
    REQUIRE(h.session.redo());
    CHECK(h.session.curve() == after);
}

TEST_CASE("Handle gizmo: the handle tool places a handle where the pointer meets the surface", "[editor][gizmo]") {
    OpenScene box("fig04-box-bend.json");
    EditorSession& session = box.session;
    const Camera& camera = box.camera;
    ToolController& tools = box.tools;
    tools.tool = Tool::handle;
    const double x = 400.0, y = 330.0;
    const auto hit = pick_surface(camera.ray(x, y, kViewport), session.positions(), session.triangles());
    REQUIRE(hit);
    REQUIRE(tools.press(session, camera, kViewport, x, y));
    tools.release(session);
    const CurveSpec& c = session.curve().curve;
    REQUIRE(c.is_handle);
    CHECK(glm::length(c.from.position - hit->position) < 1e-12);
    CHECK(glm::dot(c.from.normal, camera.forward()) < 0.0);
    CHECK(std::abs(glm::length(c.from.normal) - 1.0) < 1e-12);
    CHECK(std::abs(glm::dot(c.from.normal, c.from.binormal)) < 1e-12);
    CHECK(glm::length(c.to.position - (c.from.position + 0.25 * session.diagonal() * c.from.normal)) < 1e-12);
    CHECK(tools.tool == Tool::navigate);
    CHECK(session.history().undo_count() == 1);
    CHECK(tools.gizmo(session, camera, kViewport));
}

TEST_CASE("Handle gizmo: the dragged session saved as a scene deforms the same in vfsd deform", "[editor][gizmo]") {
    test::ScratchDir dir;
    HandleScene h;
    Scene before = h.session.current_scene();
    before.target_time = 1.0;
    const std::vector<Vec3> undragged = deform_scene(before);
    pointer_drag(h, GizmoPart::axis_z, 6, [](glm::dvec2 grab, int k) { return grab + glm::dvec2(4.0 * k, -4.0 * k); });
    const glm::dvec2 centre = h.gizmo().centre();
    pointer_drag(h, GizmoPart::ring_x, 8, [&](glm::dvec2 grab, int k) { return turned_on_screen(grab, centre, -5.0 * k); });
    h.session.set_target_time(1.0);
    run_to_target(h.session);
    REQUIRE(h.session.time() == 1.0);
    REQUIRE(h.session.current_scene().target_time == 1.0);
    const std::string path = dir.file("dragged.json");
    h.session.save_scene(path);

    const Scene saved = load_scene(path);
    REQUIRE(saved.motion.curve.is_handle);
    CHECK(glm::length(saved.motion.curve.to.position - h.target().position) < 1e-12);
    CHECK(glm::length(saved.motion.curve.to.normal - h.target().normal) < 1e-12);
    CHECK(deform_scene(saved) == h.session.positions());

    // The command-line tool itself (PLY: float32 positions); the undragged handle
    // ends elsewhere.
    const std::string out = dir.file("cli.ply");
    REQUIRE(std::system(("'" VFSD_CLI_PATH "' deform '" + path + "' --out '" + out + "' >/dev/null 2>&1").c_str()) == 0);
    const TriangleMesh cli = load_mesh(out);
    REQUIRE(cli.vertex_count() == h.session.positions().size());
    double worst = 0.0, moved = 0.0;
    for (std::size_t v = 0; v < cli.vertex_count(); ++v) {
        worst = std::max(worst, glm::length(cli.positions[v] - h.session.positions()[v]));
        moved = std::max(moved, glm::length(undragged[v] - h.session.positions()[v]));
    }
    CHECK(worst < 1e-6 * h.session.diagonal());
    CHECK(moved > 0.05 * h.session.diagonal());
}

TEST_CASE("Handle gizmo: scripts place a handle and drag its parts", "[editor][gizmo][script]") {
    OpenScene box("fig04-box-bend.json");
    EditorSession& session = box.session;
    ToolController& tools = box.tools;
    QuietHost host;
    ScriptRunner script(parse_script("{\"action\": \"place-handle\", \"at\": [400, 330]}\n"
                                     "{\"action\": \"gizmo\", \"part\": \"ring-z\", \"degrees\": 40}\n"
                                     "{\"action\": \"gizmo\", \"part\": \"centre\", \"by\": [30, -10]}\n"
                                     "{\"action\": \"expect\", \"undo_count\": 3}\n",
                                     "gizmo.jsonl"));
    EditorSettings settings;
    while (script.run_frame({session, tools, box.camera, settings, kViewport, host})) {}
    INFO(script.error());
    REQUIRE(!script.failed());
    const CurveSpec& c = session.curve().curve;
    REQUIRE(c.is_handle);
    // 40 degrees about the handle's normal: m̂ stays, ŵ turns by 40 degrees.
    CHECK(glm::length(c.to.normal - c.from.normal) < 1e-9);
    CHECK(std::abs(glm::dot(c.to.binormal, c.from.binormal)) == Approx(std::cos(glm::radians(40.0))).margin(1e-9));
    CHECK(c.to.position != c.from.position + 0.25 * session.diagonal() * c.from.normal);
    CHECK_THROWS_WITH(parse_gizmo_part("ring-w"), Catch::Contains("ring-x"));
}
