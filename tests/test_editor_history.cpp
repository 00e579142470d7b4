// Undo and redo in the editor: every region edit, curve edit and applied
// deformation is reverted and re-applied exactly.

#include <catch2/catch.hpp>

#include <cmath>

#include "deform/quality.h"
#include "editor/session.h"
#include "mesh/geometry.h"
#include "region/selectors.h"

using namespace vfsd;
using namespace vfsd::editor;

namespace {

struct Snapshot {
    std::vector<Vec3> positions;
    std::vector<double> s;
    std::vector<std::uint8_t> labels;
    std::vector<double> paint_s;
    std::vector<Vec3> control_points;
    RegionSource::Kind region_kind;
    bool operator==(const Snapshot& o) const {
        return positions == o.positions && s == o.s && labels == o.labels && paint_s == o.paint_s &&
               control_points == o.control_points && region_kind == o.region_kind;
    }
};

Snapshot snapshot(const EditorSession& session) {
    return {session.base_positions(), session.s(),          session.paint().labels,
            session.paint().s,        session.control_points(), session.region().kind};
}

Scene box_scene() {
    Scene scene = load_scene(VFSD_SOURCE_DIR "/assets/scenes/fig04-box-bend.json");
    scene.options.steps = 30;
    return scene;
}

SurfacePoint at_vertex_nearest(const EditorSession& session, Vec3 p) {
    return surface_point_at_vertex(session.triangles(), session.base_positions().size(),
                                   nearest_vertex(session.base_positions(), p));
}

void run_to_target(EditorSession& session) {
    while (session.moving()) session.update(7);
}

}  // namespace

TEST_CASE("EditHistory: undo and redo restore every state exactly", "[editor][history]") {
    EditorSession session;
    session.open_scene(box_scene());
    std::vector<Snapshot> states = {snapshot(session)};

    BrushSettings inner;
    inner.tool = BrushTool::paint_inner;
    inner.radius = 0.2;
    session.brush(at_vertex_nearest(session, {0.5, 0.0, 0.0}), inner);
    states.push_back(snapshot(session));
    CHECK(session.region().kind == RegionSource::Kind::labels);

    session.move_control_point(3, session.control_points()[3] + Vec3(0.1, 0.2, 0.0));
    states.push_back(snapshot(session));

    session.pick_geodesic(nearest_vertex(session.base_positions(), {0.0, 0.0, 0.5}), 0.1, 0.4);
    states.push_back(snapshot(session));

    BrushSettings field;
    field.tool = BrushTool::paint_s;
    field.radius = 0.3;
    field.s_target = 0.0;
    session.brush(at_vertex_nearest(session, {0.0, 0.5, 0.0}), field);
    states.push_back(snapshot(session));

    session.set_target_time(0.5);
    run_to_target(session);
    session.apply();
    states.push_back(snapshot(session));
    CHECK(session.time() == 0.0);
    CHECK(states.back().positions != states.front().positions);

    REQUIRE(session.history().undo_count() == 5);
    for (int k = 4; k >= 0; --k) {
        REQUIRE(session.undo());
        CHECK(snapshot(session) == states[k]);
    }
    CHECK_FALSE(session.undo());
    for (int k = 1; k <= 5; ++k) {
        REQUIRE(session.redo());
        CHECK(snapshot(session) == states[k]);
    }
    CHECK_FALSE(session.redo());
}

TEST_CASE("EditHistory: a stroke or a drag is one undo step; a new edit clears redo", "[editor][history]") {
    EditorSession session;
    session.open_scene(box_scene());
    const Snapshot start = snapshot(session);
    BrushSettings outer;
    outer.tool = BrushTool::paint_outer;
    outer.radius = 0.15;
    session.begin_region_gesture();
    for (const Vec3 p : {Vec3(0.5, 0.0, -0.2), Vec3(0.5, 0.2, -0.1), Vec3(0.5, 0.4, 0.0)})
        session.brush(at_vertex_nearest(session, p), outer);
    session.end_region_gesture("paint outer");
    session.begin_curve_gesture();
    for (int k = 1; k <= 5; ++k) session.move_control_point(2, session.control_points()[2] + Vec3(0.0, 0.0, 0.02));
    session.end_curve_gesture("move control point 2");
    CHECK(session.history().undo_count() == 2);
    REQUIRE(session.undo());
    REQUIRE(session.undo());
    CHECK(snapshot(session) == start);
    CHECK(session.history().redo_count() == 2);
    session.add_segment();
    CHECK(session.control_points().size() == 7);
    CHECK(session.history().redo_count() == 0);
}

TEST_CASE("EditHistory: undo of a curve edit restarts the deformation from t = 0", "[editor][history]") {
    EditorSession session;
    session.open_scene(box_scene());
    session.move_control_point(3, session.control_points()[3] + Vec3(0.0, 0.0, 0.2));
    session.set_target_time(1.0);
    run_to_target(session);
    const std::vector<Vec3> result = session.positions();
    REQUIRE(session.undo());
    CHECK(session.time() == 0.0);
    CHECK(session.target_time() == 1.0);
    REQUIRE(session.redo());
    run_to_target(session);
    CHECK(session.positions() == result);
}

TEST_CASE("Regions a user can reason about: the first stroke starts clean, the band blends, the curve follows",
          "[editor][history][region]") {
    EditorSession session;
    session.open_mesh("builtin:bar");  // a geodesic region around the highest vertex
    const double d = session.diagonal();
    const std::vector<Vec3> curve_before = session.control_points();
    const Snapshot opened = snapshot(session);
    const auto& p = session.base_positions();
    const std::size_t lowest = std::min_element(p.begin(), p.end(), [](const Vec3& a, const Vec3& b) {
                                   return a.z < b.z;
                               }) - p.begin();
    BrushSettings inner;
    inner.radius = 0.1 * d;
    session.brush(at_vertex_nearest(session, p[lowest]), inner);

    // Only what was painted is labelled: inner within the brush, no outer at all.
    REQUIRE(session.region().kind == RegionSource::Kind::labels);
    const std::vector<std::uint8_t>& labels = session.paint().labels;
    for (std::size_t v = 0; v < labels.size(); ++v) {
        CHECK(labels[v] != std::uint8_t(RegionLabel::outer));
        if (labels[v] == std::uint8_t(RegionLabel::inner)) CHECK(glm::length(p[v] - p[lowest]) <= inner.radius * 1.001);
    }
    // The inner region alone blends over the default band: s is 0 there, 1 far off, between in the band.
    CHECK(session.region_band() == Approx(EditorSession::kDefaultBandFraction * d));
    std::size_t blend = 0;
    for (std::size_t v = 0; v < labels.size(); ++v) {
        if (labels[v] == std::uint8_t(RegionLabel::inner)) CHECK(session.s()[v] == 0.0);
        if (glm::length(p[v] - p[lowest]) > inner.radius + session.region_band() * 1.5) CHECK(session.s()[v] == 1.0);
        blend += session.s()[v] > 0.0 && session.s()[v] < 1.0;
    }
    CHECK(blend > 0);

    // The curve starts at the new inner region's centroid, its shape kept.
    const std::vector<Vec3> curve_after = session.control_points();
    Vec3 centroid(0.0);
    int count = 0;
    for (std::size_t v = 0; v < p.size(); ++v)
        if (session.s()[v] <= 0.0) centroid += p[v], ++count;
    centroid /= double(count);
    CHECK(glm::length(curve_after.front() - centroid) < 1e-9 * d);
    for (std::size_t i = 0; i < curve_after.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            CHECK(glm::length(curve_after[i] - curve_after[j]) ==
                  Approx(glm::length(curve_before[i] - curve_before[j])).epsilon(1e-9));

    // One undo step brings region and curve back; redo repeats both.
    const Snapshot painted = snapshot(session);
    REQUIRE(session.undo());
    CHECK(snapshot(session) == opened);
    REQUIRE(session.redo());
    CHECK(snapshot(session) == painted);

    // A wider band widens the blend; a new region is clean again; each one undo step.
    session.set_region_band(2.0 * session.region_band());
    std::size_t wider = 0;
    for (const double s : session.s()) wider += s > 0.0 && s < 1.0;
    CHECK(wider > blend);
    session.new_region();
    for (const std::uint8_t l : session.paint().labels) CHECK(l == 0);
    CHECK(session.history().undo_count() == 3);
    REQUIRE(session.undo());
    REQUIRE(session.undo());
    CHECK(snapshot(session) == painted);
    CHECK_THROWS_AS(session.set_region_band(-1.0), InputError);
}

TEST_CASE("Apply: its undo plays back to the applied pose, redo applies again; the stats count since opened",
          "[editor][history][apply]") {
    EditorSession session;
    session.open_scene(box_scene());
    const std::vector<Vec3> opened = session.base_positions();
    const auto& triangles = session.triangles();
    const double opened_volume = signed_volume(opened, triangles);
    session.set_target_time(0.6);
    run_to_target(session);
    const std::vector<Vec3> pose = session.positions();
    const double pose_volume = signed_volume(pose, triangles);
    const SessionStats first = session.stats();
    REQUIRE(first.volume_error_percent > 0.0);
    CHECK_FALSE(first.applied);
    CHECK(first.volume_error_since_opened_percent == first.volume_error_percent);
    CHECK(first.flipped_since_opened == first.flipped_triangles);

    session.apply();
    CHECK(session.time() == 0.0);
    CHECK(session.target_time() == 0.0);
    // At rest the stats still say what the apply did to the mesh as opened.
    CHECK(session.stats().applied);
    CHECK(session.stats().volume_error_percent == 0.0);
    CHECK(session.stats().volume_error_since_opened_percent == first.volume_error_percent);
    CHECK(session.stats().flipped_since_opened == first.flipped_triangles);

    // A further edit: the since-opened figures are against the mesh as opened,
    // the edit's own against the applied pose.
    session.set_target_time(1.0);
    run_to_target(session);
    const SessionStats second = session.stats();
    const double volume = signed_volume(session.positions(), triangles);
    CHECK(second.volume_error_since_opened_percent ==
          Approx(100.0 * std::abs(volume - opened_volume) / std::abs(opened_volume)).epsilon(1e-9));
    CHECK(second.volume_error_percent ==
          Approx(100.0 * std::abs(volume - pose_volume) / std::abs(pose_volume)).epsilon(1e-9));
    CHECK(second.volume_error_since_opened_percent != second.volume_error_percent);
    CHECK(second.flipped_since_opened == flipped_triangle_list(opened, session.positions(), triangles).size());
    CHECK(volume_stat_text(second).find("since opened (this edit ") != std::string::npos);
    CHECK(flipped_stat_text(second).find(std::to_string(second.flipped_since_opened) + " since opened (this edit ") == 0);

    // Undo: the base as opened, the target back at the applied pose's t, which
    // the deformation reaches again with the same positions.
    REQUIRE(session.undo());
    CHECK(session.base_positions() == opened);
    CHECK(session.target_time() == 0.6);
    CHECK_FALSE(session.stats().applied);
    run_to_target(session);
    CHECK(session.time() == 0.6);
    CHECK(session.positions() == pose);
    CHECK(volume_stat_text(session.stats()).find("this edit") == std::string::npos);

    // Redo bakes the pose again, at rest.
    REQUIRE(session.redo());
    CHECK(session.base_positions() == pose);
    CHECK(session.target_time() == 0.0);
    CHECK(session.time() == 0.0);
    CHECK(session.stats().volume_error_since_opened_percent == first.volume_error_percent);
}
