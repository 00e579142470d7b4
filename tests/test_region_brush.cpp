// Brushes on the region: each stroke is one undoable RegionEdit.
#include <catch2/catch.hpp>

#include <algorithm>

#include "base/error.h"
#include "mesh/vertex_rings.h"
#include "region/brush.h"
#include "test_region_meshes.h"

using namespace vfsd;

namespace {

struct Sheet {
    TriangleMesh mesh = vfsd::test::grid_mesh(30, 1.0);  // edge length 1/30
    VertexRings rings = build_vertex_rings(mesh);
};

// A surface point at the centroid of the lower triangle of quad (i, j).
SurfacePoint at_quad(int i, int j) { return {static_cast<std::uint32_t>(2 * (j * 30 + i)), Vec3(1.0 / 3.0)}; }

}  // namespace

TEST_CASE("label brushes paint within the geodesic radius and revert exactly", "[region][brush]") {
    Sheet sh;
    const auto& p = sh.mesh.positions;
    RegionPaint paint = make_region_paint(p.size());
    const SurfacePoint centre = at_quad(10, 12);
    const Vec3 x = surface_position(p, sh.mesh.triangles, centre);
    const RegionEdit e = label_brush(paint, p, sh.mesh.triangles, sh.rings, centre, 0.2, LabelBrush::paint_inner);
    CHECK(std::is_sorted(e.vertices.begin(), e.vertices.end()));
    const RegionPaint before = paint;
    apply_edit(paint, e);
    for (std::size_t v = 0; v < p.size(); ++v) {
        const double d = glm::length(p[v] - x);  // flat sheet: geodesic = Euclidean
        if (d < 0.18) CHECK(paint.labels[v] == static_cast<std::uint8_t>(RegionLabel::inner));
        if (d > 0.22) CHECK(paint.labels[v] == static_cast<std::uint8_t>(RegionLabel::none));
    }
    // Outer paint over part of it, then erase: each step reverts to the exact previous state.
    const RegionPaint after_inner = paint;
    const RegionEdit o = label_brush(paint, p, sh.mesh.triangles, sh.rings, at_quad(16, 12), 0.15, LabelBrush::paint_outer);
    apply_edit(paint, o);
    CHECK(std::count(paint.labels.begin(), paint.labels.end(), 2) > 0);
    const RegionEdit er = label_brush(paint, p, sh.mesh.triangles, sh.rings, centre, 0.5, LabelBrush::erase);
    apply_edit(paint, er);
    const auto inner_left = label_mask(paint, RegionLabel::inner);
    CHECK(std::count(inner_left.begin(), inner_left.end(), 1) == 0);
    revert_edit(paint, er);
    revert_edit(paint, o);
    CHECK(paint.labels == after_inner.labels);
    revert_edit(paint, e);
    CHECK(paint.labels == before.labels);
    CHECK(paint.s == before.s);
}

TEST_CASE("the field brush falls off smoothly, stays in [0, 1] and reverts exactly", "[region][brush]") {
    Sheet sh;
    const auto& p = sh.mesh.positions;
    RegionPaint paint = make_region_paint(p.size());
    for (std::size_t v = 0; v < p.size(); ++v) paint.s[v] = 0.5 + 0.5 * std::sin(7.0 * p[v].x) * std::cos(5.0 * p[v].y);
    const RegionPaint before = paint;
    const SurfacePoint centre = at_quad(15, 15);
    const Vec3 x = surface_position(p, sh.mesh.triangles, centre);
    const RegionEdit e = field_brush(paint, p, sh.mesh.triangles, sh.rings, centre, 0.25, 0.0, 0.8);
    apply_edit(paint, e);
    for (std::size_t v = 0; v < p.size(); ++v) {
        const double d = glm::length(p[v] - x);
        CHECK(paint.s[v] >= 0.0);
        CHECK(paint.s[v] <= before.s[v]);  // target 0 only lowers s
        if (d > 0.27) CHECK(paint.s[v] == before.s[v]);
        // Near the centre the weight is about 1: s drops to about (1 - 0.8) of its value.
        if (d < 0.03) CHECK(paint.s[v] <= 0.25 * before.s[v] + 1e-12);
    }
    revert_edit(paint, e);
    CHECK(paint.s == before.s);
}

TEST_CASE("a stroke of several dabs merges into one edit", "[region][brush]") {
    Sheet sh;
    const auto& p = sh.mesh.positions;
    RegionPaint paint = make_region_paint(p.size());
    const RegionPaint before = paint;
    RegionEdit stroke{RegionChannel::s, {}, {}, {}};
    for (int i = 5; i < 20; i += 3) {  // overlapping dabs along a drag
        const RegionEdit dab = field_brush(paint, p, sh.mesh.triangles, sh.rings, at_quad(i, 10), 0.12, 0.0, 0.5);
        apply_edit(paint, dab);
        merge_edit(stroke, dab);
    }
    const RegionPaint painted = paint;
    CHECK(std::is_sorted(stroke.vertices.begin(), stroke.vertices.end()));
    CHECK(std::adjacent_find(stroke.vertices.begin(), stroke.vertices.end()) == stroke.vertices.end());
    revert_edit(paint, stroke);
    CHECK(paint.s == before.s);
    apply_edit(paint, stroke);
    CHECK(paint.s == painted.s);
    CHECK_THROWS_AS(merge_edit(stroke, RegionEdit{RegionChannel::labels, {}, {}, {}}), InputError);
}

TEST_CASE("brushes and edits reject bad input", "[region][brush]") {
    Sheet sh;
    const auto& p = sh.mesh.positions;
    RegionPaint paint = make_region_paint(p.size());
    const auto& t = sh.mesh.triangles;
    CHECK_THROWS_AS(label_brush(paint, p, t, sh.rings, at_quad(1, 1), 0.0, LabelBrush::erase), InputError);
    CHECK_THROWS_AS(field_brush(paint, p, t, sh.rings, at_quad(1, 1), 0.1, 1.5, 0.5), InputError);
    CHECK_THROWS_AS(field_brush(paint, p, t, sh.rings, at_quad(1, 1), 0.1, 0.5, -0.1), InputError);
    CHECK_THROWS_AS(label_brush(make_region_paint(3), p, t, sh.rings, at_quad(1, 1), 0.1, LabelBrush::erase), InputError);
    CHECK_THROWS_AS(apply_edit(paint, RegionEdit{RegionChannel::s, {100000}, {1.0}, {0.0}}), InputError);
    CHECK_THROWS_AS(apply_edit(paint, RegionEdit{RegionChannel::labels, {1}, {0.0}, {7.0}}), InputError);
    CHECK_THROWS_AS(apply_edit(paint, RegionEdit{RegionChannel::s, {1, 2}, {1.0}, {0.0}}), InputError);
}
