// Dragging the curve's end knot: over the mesh (outside the inner region) it lands
// on the surface point under the pointer; off the mesh it stays on the plane
// through its start facing the view; an axis drag ignores the surface; the last
// segment is turned and scaled along, keeping its shape (its handedness too, when
// dragged straight back); the drag is one undo step.

#include <catch2/catch.hpp>

#include "editor/picking.h"
#include "editor/session.h"
#include "editor/tools.h"
#include "view/camera.h"

using namespace vfsd;
using namespace vfsd::editor;

namespace {

const Viewport kViewport{800, 600};

glm::dvec2 pixel(const Camera& camera, const Vec3& p) {
    const glm::dvec3 s = camera.project(p, kViewport);
    return {s.x, s.y};
}

// A sphere with its default region and curve, framed, and a pixel on the sphere
// outside the inner region (s > 0 at the hit) and one off the mesh.
struct EndDrag {
    EditorSession session;
    Camera camera;
    ToolController tools;
    std::size_t end = 0;

    EndDrag() {
        session.open_mesh("builtin:sphere");
        std::vector<Vec3> points = session.base_positions();
        for (const Vec3& p : session.control_points()) points.push_back(p);
        camera.frame(points, kViewport.aspect());
        tools.adapt_to(session);
        end = session.control_points().size() - 1;
    }
    // Presses on the end knot's pixel, moves to (x, y), releases.
    void drag_end_to(glm::dvec2 to) {
        const glm::dvec2 from = pixel(camera, session.control_points()[end]);
        REQUIRE(tools.press(session, camera, kViewport, from.x, from.y));
        REQUIRE(tools.dragged_point() == end);
        tools.drag(session, camera, kViewport, (from.x + to.x) / 2, (from.y + to.y) / 2);
        tools.drag(session, camera, kViewport, to.x, to.y);
        tools.release(session);
    }
    double s_at(const SurfaceHit& hit) const {
        const Triangle& t = session.triangles()[hit.point.triangle];
        const Vec3& w = hit.point.barycentric;
        return w[0] * session.s()[t[0]] + w[1] * session.s()[t[1]] + w[2] * session.s()[t[2]];
    }
    // A pixel over the sphere whose hit lies outside the inner region.
    std::optional<std::pair<glm::dvec2, SurfaceHit>> outer_pixel() const {
        for (int y = 20; y < kViewport.height; y += 20)
            for (int x = 20; x < kViewport.width; x += 20)
                if (const auto hit = session.pick_surface(camera.ray(x, y, kViewport)); hit && s_at(*hit) > 0.5)
                    return std::make_pair(glm::dvec2(x, y), *hit);
        return std::nullopt;
    }
};

}  // namespace

TEST_CASE("End knot drag: over the mesh the end lands on the surface under the pointer", "[editor][drag]") {
    EndDrag d;
    const auto target = d.outer_pixel();
    REQUIRE(target);
    const std::vector<Vec3> before = d.session.control_points();
    const Vec3 start = before[d.end];
    d.drag_end_to(target->first);
    const Vec3 moved = d.session.control_points()[d.end];
    // On the pointer's ray, at the surface's depth: the hit itself.
    CHECK(glm::length(moved - target->second.position) < 1e-9 * d.session.diagonal());
    const glm::dvec2 p = pixel(d.camera, moved);
    CHECK(p.x == Approx(target->first.x).margin(1e-6));
    CHECK(p.y == Approx(target->first.y).margin(1e-6));
    // Not the view plane through the start: the depth changed.
    CHECK(std::abs(glm::dot(moved - start, d.camera.forward())) > 1e-3 * d.session.diagonal());
    CHECK(d.tools.hint.empty());  // the hint lasts as long as the drag

    // The last segment keeps its shape: turned and scaled about its first knot;
    // the knots before it never moved.
    const std::vector<Vec3> after = d.session.control_points();
    for (std::size_t i = 0; i + 3 <= d.end; ++i) CHECK(after[i] == before[i]);
    const std::size_t a = d.end - 3;
    const double scale = glm::length(after[d.end] - after[a]) / glm::length(before[d.end] - before[a]);
    for (std::size_t i = a + 1; i <= d.end; ++i)
        for (std::size_t j = a; j < i; ++j)
            CHECK(glm::length(after[i] - after[j]) ==
                  Approx(scale * glm::length(before[i] - before[j])).margin(1e-9 * d.session.diagonal()));
    // One undo step brings the curve back.
    REQUIRE(d.session.undo());
    CHECK(d.session.control_points() == before);
    REQUIRE(d.session.redo());
    CHECK(d.session.control_points() == after);
}

TEST_CASE("End knot drag: off the mesh the end stays on the view plane through its start", "[editor][drag]") {
    EndDrag d;
    const glm::dvec2 off(5.0, 5.0);  // the corner: no surface there
    REQUIRE_FALSE(d.session.pick_surface(d.camera.ray(off.x, off.y, kViewport)));
    const Vec3 start = d.session.control_points()[d.end];
    d.drag_end_to(off);
    const Vec3 moved = d.session.control_points()[d.end];
    CHECK(glm::dot(moved - start, d.camera.forward()) == Approx(0.0).margin(1e-9));
    const glm::dvec2 p = pixel(d.camera, moved);
    CHECK(p.x == Approx(off.x).margin(1e-6));
    CHECK(p.y == Approx(off.y).margin(1e-6));
    REQUIRE(d.session.undo());
    CHECK(d.session.control_points()[d.end] == start);
}

TEST_CASE("End knot drag: an axis drag and the inner knots ignore the surface", "[editor][drag]") {
    EndDrag d;
    const auto target = d.outer_pixel();
    REQUIRE(target);
    const Vec3 start = d.session.control_points()[d.end];
    d.tools.axis = 2;
    d.drag_end_to(target->first);
    const Vec3 moved = d.session.control_points()[d.end];
    CHECK(moved.x == start.x);
    CHECK(moved.y == start.y);

    // The knot before the end (a Bezier handle point) moves on its view plane.
    EndDrag e;
    const std::size_t inner = e.end - 1;
    const Vec3 from = e.session.control_points()[inner];
    e.tools.press_control_point(e.session, inner);
    e.tools.drag(e.session, e.camera, kViewport, target->first.x, target->first.y);
    e.tools.release(e.session);
    CHECK(glm::dot(e.session.control_points()[inner] - from, e.camera.forward()) == Approx(0.0).margin(1e-9));
}

TEST_CASE("End knot drag: the inner region, which moves with the end, is no place to land", "[editor][drag]") {
    EndDrag d;
    // A pixel over the inner region (s = 0 at the hit), if the view shows one.
    std::optional<glm::dvec2> over_inner;
    for (int y = 10; y < kViewport.height && !over_inner; y += 10)
        for (int x = 10; x < kViewport.width && !over_inner; x += 10)
            if (const auto hit = d.session.pick_surface(d.camera.ray(x, y, kViewport)); hit && d.s_at(*hit) <= 0.0)
                over_inner = glm::dvec2(x, y);
    REQUIRE(over_inner);
    const Vec3 start = d.session.control_points()[d.end];
    d.drag_end_to(*over_inner);
    CHECK(glm::dot(d.session.control_points()[d.end] - start, d.camera.forward()) == Approx(0.0).margin(1e-9));
}

TEST_CASE("End knot drag: dragged straight back through its start, the segment is turned, not mirrored",
          "[editor][drag]") {
    EndDrag d;
    const std::size_t a = d.end - 3;
    // A segment out of one plane, so that a mirror image differs from every turn of it.
    const double r = 0.1 * d.session.diagonal();
    d.session.move_control_point(d.end - 1, d.session.control_points()[d.end - 1] + r * d.camera.forward());
    const std::vector<Vec3> before = d.session.control_points();
    const auto handedness = [&](const std::vector<Vec3>& p) {
        return glm::dot(glm::cross(p[a + 1] - p[a], p[a + 2] - p[a]), p[a + 3] - p[a]);
    };
    REQUIRE(std::abs(handedness(before)) > 1e-3 * r * r * r);
    // The pointer goes to where the end's mirror image through the segment's start shows.
    d.drag_end_to(pixel(d.camera, 2.0 * before[a] - before[d.end]));
    const std::vector<Vec3> after = d.session.control_points();
    CHECK(glm::dot(after[d.end] - after[a], before[d.end] - before[a]) < 0.0);  // it went back
    CHECK(after[a] == before[a]);
    // A turn and a scale keep the segment's handedness; a mirror image reverses it.
    const double scale = glm::length(after[d.end] - after[a]) / glm::length(before[d.end] - before[a]);
    CHECK(handedness(after) == Approx(scale * scale * scale * handedness(before)).epsilon(1e-6));
}
