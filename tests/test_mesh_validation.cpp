// The validation report (mesh/validation.h): each flag is raised by its own broken
// mesh and by nothing else, and boundary loops come out ordered.

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "mesh/validation.h"
#include "mesh_fixtures.h"

using namespace vfsd;

namespace {

// The number of entries in each problem list, in a fixed order.
struct Flags {
    std::size_t out_of_range, non_finite, degenerate, duplicate, isolated, non_manifold_edges, non_manifold_vertices,
        boundary_edges;
    bool operator==(const Flags& o) const {
        return out_of_range == o.out_of_range && non_finite == o.non_finite && degenerate == o.degenerate &&
               duplicate == o.duplicate && isolated == o.isolated && non_manifold_edges == o.non_manifold_edges &&
               non_manifold_vertices == o.non_manifold_vertices && boundary_edges == o.boundary_edges;
    }
};

std::ostream& operator<<(std::ostream& os, const Flags& f) {
    return os << "{range " << f.out_of_range << ", non-finite " << f.non_finite << ", degenerate " << f.degenerate
              << ", duplicate " << f.duplicate << ", isolated " << f.isolated << ", nm-edges " << f.non_manifold_edges
              << ", nm-vertices " << f.non_manifold_vertices << ", boundary " << f.boundary_edges << "}";
}

Flags flags_of(const ValidationReport& r) {
    return {r.out_of_range_triangles.size(), r.non_finite_vertices.size(), r.degenerate_triangles.size(),
            r.duplicate_triangles.size(),    r.isolated_vertices.size(),   r.non_manifold_edges.size(),
            r.non_manifold_vertices.size(),  r.boundary_edges.size()};
}

// Two tetrahedra; the second's apex is the first's vertex 0 (a pinch when shared).
TriangleMesh two_tetrahedra(bool share_vertex) {
    TriangleMesh m;
    const Vec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const Triangle faces[4] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (int copy = 0; copy < 2; ++copy) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (const Vec3& q : p) m.positions.push_back(copy ? -q : q);
        for (const Triangle& f : faces) m.triangles.push_back(Triangle(base) + f);
    }
    if (share_vertex) {  // merge vertex 4 into 0 (both at the origin)
        for (Triangle& t : m.triangles)
            for (int k = 0; k < 3; ++k)
                if (t[k] == 4) t[k] = 0;
        for (Triangle& t : m.triangles)
            for (int k = 0; k < 3; ++k)
                if (t[k] > 4) --t[k];
        m.positions.erase(m.positions.begin() + 4);
    }
    return m;
}

}  // namespace

TEST_CASE("a clean cube raises no flag", "[mesh][validation]") {
    const ValidationReport r = validate_mesh(fixtures::cube());
    CHECK(flags_of(r) == Flags{});
    CHECK(r.is_closed);
    CHECK(r.is_manifold);
    CHECK(r.reasons.empty());
    CHECK(r.warnings.empty());
    CHECK(r.boundary_loops.empty());
    CHECK(r.valence_min == 4);
    CHECK(r.valence_max == 6);
    CHECK(r.valence_histogram[4] + r.valence_histogram[5] + r.valence_histogram[6] == 8);
    CHECK(flags_of(validate_mesh(two_tetrahedra(false))) == Flags{});
}

TEST_CASE("each validation flag has its own trigger", "[mesh][validation]") {
    TriangleMesh m = fixtures::cube();
    Flags expect{};
    bool manifold = true, closed = true;

    SECTION("index out of range") {
        m.triangles.push_back({0, 1, 100});
        expect.out_of_range = 1;
        manifold = false;
    }
    SECTION("non-finite coordinate") {
        m.positions[3].y = std::numeric_limits<double>::quiet_NaN();
        expect.non_finite = 1;
        expect.degenerate = 0;
    }
    SECTION("repeated index") {
        m.triangles.push_back({2, 5, 2});
        expect.degenerate = 1;
        manifold = false;
    }
    SECTION("zero area") {
        // Move a corner of triangle 0 onto the midpoint of its opposite edge.
        const Triangle t = m.triangles[0];
        m.positions[t[2]] = 0.5 * (m.positions[t[0]] + m.positions[t[1]]);
        expect.degenerate = 1;
    }
    SECTION("duplicate triangle") {
        const Triangle t = m.triangles[0];
        m.triangles.push_back({t[1], t[2], t[0]});
        expect.duplicate = 1;
        expect.non_manifold_edges = 3;
        expect.non_manifold_vertices = 3;
        manifold = false;
    }
    SECTION("isolated vertex") {
        m.positions.push_back(Vec3(5.0));
        expect.isolated = 1;
    }
    SECTION("edge of three triangles") {
        m.positions.push_back(Vec3(0.0, 0.0, 3.0));
        const Triangle t = m.triangles[0];
        m.triangles.push_back({t[0], t[1], 8});
        expect.non_manifold_edges = 1;
        expect.non_manifold_vertices = 2;
        expect.boundary_edges = 2;
        manifold = closed = false;
    }
    SECTION("inconsistent orientation") {
        std::swap(m.triangles[5][1], m.triangles[5][2]);
        expect.non_manifold_edges = 3;
        manifold = false;
    }
    SECTION("pinched vertex") {
        m = two_tetrahedra(true);
        expect.non_manifold_vertices = 1;
        manifold = false;
    }
    SECTION("missing triangle") {
        m.triangles.pop_back();
        expect.boundary_edges = 3;
        closed = false;
    }
    const ValidationReport r = validate_mesh(m);
    CHECK(flags_of(r) == expect);
    CHECK(r.is_manifold == manifold);
    CHECK(r.is_closed == closed);
    CHECK(r.reasons.empty() == manifold);
}

TEST_CASE("the pinched vertex and the crowded edge are named", "[mesh][validation]") {
    const ValidationReport pinch = validate_mesh(two_tetrahedra(true));
    REQUIRE(pinch.non_manifold_vertices.size() == 1);
    CHECK(pinch.non_manifold_vertices[0] == 0);
    REQUIRE(pinch.reasons.size() == 1);
    CHECK(pinch.reasons[0].find("more than one fan") != std::string::npos);

    TriangleMesh fin = fixtures::grid(1, 1);  // triangles (0,1,3), (0,3,2): diagonal 0-3
    fin.positions.push_back(Vec3(0.5, 0.5, 1.0));
    fin.triangles.push_back({0, 3, 4});
    const ValidationReport r = validate_mesh(fin);
    REQUIRE(r.non_manifold_edges.size() == 1);
    CHECK(r.non_manifold_edges[0].from == 0);
    CHECK(r.non_manifold_edges[0].to == 3);
}

TEST_CASE("boundary loops of a grid and an annulus", "[mesh][validation]") {
    SECTION("grid: one loop around the outside, counter-clockwise") {
        const TriangleMesh g = fixtures::grid(5, 3);
        const ValidationReport r = validate_mesh(g);
        CHECK_FALSE(r.is_closed);
        CHECK(r.is_manifold);
        REQUIRE(r.boundary_loops.size() == 1);
        const auto& loop = r.boundary_loops[0];
        REQUIRE(loop.size() == 2 * (5 + 3));
        // Consecutive loop vertices are one grid step apart, and the loop's signed
        // area in the plane is the grid's (+15): counter-clockwise seen from +z.
        double twice_area = 0.0;
        for (std::size_t i = 0; i < loop.size(); ++i) {
            const Vec3 a = g.positions[loop[i]], b = g.positions[loop[(i + 1) % loop.size()]];
            CHECK(glm::length(b - a) == 1.0);
            twice_area += a.x * b.y - b.x * a.y;
        }
        CHECK(twice_area == 30.0);
    }
    SECTION("annulus: two loops of equal length, opposite senses") {
        const TriangleMesh a = fixtures::annulus(12, 3);
        const ValidationReport r = validate_mesh(a);
        CHECK(r.is_manifold);
        REQUIRE(r.boundary_loops.size() == 2);
        double areas[2] = {0.0, 0.0};
        for (int l = 0; l < 2; ++l) {
            const auto& loop = r.boundary_loops[l];
            CHECK(loop.size() == 12);
            for (std::size_t i = 0; i < loop.size(); ++i) {
                const Vec3 p = a.positions[loop[i]], q = a.positions[loop[(i + 1) % loop.size()]];
                areas[l] += p.x * q.y - q.x * p.y;
            }
        }
        // The outer loop runs counter-clockwise, the inner one clockwise.
        CHECK(areas[0] * areas[1] < 0.0);
    }
}

TEST_CASE("chain_boundary_loops follows edges in their direction", "[mesh][validation]") {
    const std::vector<ValidationReport::Edge> edges = {{2, 0}, {5, 6}, {0, 1}, {1, 2}, {6, 5}};
    const auto loops = chain_boundary_loops(edges, 7);
    REQUIRE(loops.size() == 2);
    CHECK(loops[0] == std::vector<std::uint32_t>{2, 0, 1});
    CHECK(loops[1] == std::vector<std::uint32_t>{5, 6});
}

TEST_CASE("validation scales to large meshes", "[mesh][validation]") {
    const TriangleMesh sphere = make_builtin_mesh("sphere", 7);  // 163,842 vertices
    const ValidationReport r = validate_mesh(sphere);
    CHECK(r.is_closed);
    CHECK(r.is_manifold);
    CHECK(r.valence_histogram[5] == 12);
    CHECK(r.valence_histogram[6] == sphere.vertex_count() - 12);
}
