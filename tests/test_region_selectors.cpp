// Vertex selectors of the scene file contract: parsing, union, nearest vertex.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include "base/error.h"
#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "mesh/vertex_rings.h"
#include "region/region_field.h"
#include "region/selectors.h"
#include "test_region_meshes.h"

using namespace vfsd;

TEST_CASE("selectors select the union of their shapes", "[region][selectors]") {
    const TriangleMesh m = vfsd::test::grid_mesh(10, 1.0);
    const auto sel = parse_selectors(nlohmann::json::parse(R"([
        {"sphere": [0, 0, 0, 0.25]},
        {"box": [0.7, 0.7, -1, 1, 1, 1]},
        {"halfspace": [0, -1, 0, -0.05]},
        {"vertices": [60]}
    ])"));
    REQUIRE(sel.size() == 4);
    const auto mask = select_vertices(m.positions, sel);
    for (std::size_t v = 0; v < mask.size(); ++v) {
        const Vec3 p = m.positions[v];
        const bool expected = glm::length(p) <= 0.25 || (p.x >= 0.7 && p.y >= 0.7) || -p.y >= -0.05 || v == 60;
        CHECK(static_cast<bool>(mask[v]) == expected);
    }
    // A single object is one selector; each selector alone selects a subset of the union.
    const auto one = select_vertices(m.positions, parse_selectors(nlohmann::json::parse(R"({"sphere": [0,0,0,0.25]})")));
    for (std::size_t v = 0; v < mask.size(); ++v) CHECK((!one[v] || mask[v]));
}

TEST_CASE("selector parse errors name the bad field", "[region][selectors]") {
    using nlohmann::json;
    CHECK_THROWS_WITH(parse_selectors(json::parse(R"([{"sphere": [0,0,0,1]}, {"sphere": [0,0,1]}])"), "inner"),
                      Catch::Contains("inner[1].sphere") && Catch::Contains("4 numbers"));
    CHECK_THROWS_WITH(parse_selectors(json::parse(R"({"cube": [0]})"), "outer"), Catch::Contains("outer") && Catch::Contains("cube"));
    CHECK_THROWS_WITH(parse_selectors(json::parse(R"({"box": [1,0,0,0,1,1]})")), Catch::Contains("box"));
    CHECK_THROWS_WITH(parse_selectors(json::parse(R"({"halfspace": [0,0,0,1]})")), Catch::Contains("normal"));
    CHECK_THROWS_WITH(parse_selectors(json::parse(R"({"sphere": [0,0,0,-1]})")), Catch::Contains("radius"));
    CHECK_THROWS_WITH(parse_selectors(json::parse(R"({"vertices": [1, -2]})")), Catch::Contains("vertices"));
    CHECK_THROWS_WITH(parse_selectors(json::parse(R"({"vertices": [1.5]})")), Catch::Contains("vertices"));
    CHECK_THROWS_AS(parse_selectors(json::parse(R"({"sphere": [0,0,0,1], "box": [0,0,0,1,1,1]})")), InputError);
    CHECK_THROWS_AS(parse_selectors(json::parse(R"({"sphere": [0,0,"x",1]})")), InputError);
    CHECK_THROWS_AS(parse_selectors(json::parse(R"(3)")), InputError);
    const auto far = parse_selectors(json::parse(R"({"vertices": [1000]})"));
    CHECK_THROWS_AS(select_vertices(vfsd::test::grid_mesh(2, 1.0).positions, far), InputError);
}

TEST_CASE("nearest vertex", "[region][selectors]") {
    const TriangleMesh m = vfsd::test::grid_mesh(10, 1.0);
    CHECK(nearest_vertex(m.positions, Vec3(0.31, 0.52, 0.4)) == 5 * 11 + 3);
    CHECK(nearest_vertex(m.positions, Vec3(-5.0, -5.0, 0.0)) == 0);
    CHECK_THROWS_AS(nearest_vertex({}, Vec3(0.0)), InputError);
}

TEST_CASE("selectors and eq. (16) on the built-in cylinder", "[region][selectors]") {
    const TriangleMesh m = make_builtin_mesh("cylinder");
    const VertexRings rings = build_vertex_rings(m);
    const BoundingBox box = bounding_box(m.positions);
    // The lowest and highest fifth along the longest axis: inner and outer.
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (box.extent()[k] > box.extent()[axis]) axis = k;
    Vec3 n(0.0);
    n[axis] = 1.0;
    const double lo = box.min[axis] + 0.2 * box.extent()[axis], hi = box.max[axis] - 0.2 * box.extent()[axis];
    nlohmann::json inner_json = {{{"halfspace", {-n.x, -n.y, -n.z, -lo}}}};
    nlohmann::json outer_json = {{{"halfspace", {n.x, n.y, n.z, hi}}}};
    const auto inner = select_vertices(m.positions, parse_selectors(inner_json, "inner"));
    const auto outer = select_vertices(m.positions, parse_selectors(outer_json, "outer"));
    const RegionField f = painted_region_field(m.positions, rings, inner, outer);
    CHECK(f.warnings.empty());
    for (std::size_t v = 0; v < f.s.size(); ++v) {
        if (inner[v]) REQUIRE(f.s[v] == 0.0);
        else if (outer[v]) REQUIRE(f.s[v] == 1.0);
        else REQUIRE((f.s[v] > 0.0 && f.s[v] < 1.0));
    }
}
