#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>

#include "base/error.h"
#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "mesh/subdivision.h"
#include "mesh/validation.h"
#include "mesh/vertex_rings.h"

using namespace vfsd;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Everything a clean, closed, outward-oriented mesh must satisfy.
void require_clean_closed(const TriangleMesh& mesh) {
    const ValidationReport r = validate_mesh(mesh);
    INFO("reasons: " << r.reasons.size() << ", warnings: " << r.warnings.size());
    CHECK(r.is_closed);
    CHECK(r.is_manifold);
    CHECK(r.reasons.empty());
    CHECK(r.warnings.empty());
    CHECK(r.boundary_edges.empty());
    CHECK(r.degenerate_triangles.empty());
    CHECK(signed_volume(mesh.positions, mesh.triangles) > 0.0);
}

// 1 for an equilateral triangle, 0 for a degenerate one.
double shape_quality(const Vec3& a, const Vec3& b, const Vec3& c) {
    const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
    return 4.0 * std::sqrt(3.0) * area / (glm::dot(b - a, b - a) + glm::dot(c - b, c - b) + glm::dot(a - c, a - c));
}

}  // namespace

TEST_CASE("built-in meshes: default counts near the paper's, exact volumes where the shape is exact", "[mesh][builtin]") {
    struct Expect {
        const char* name;
        std::size_t paper_vertices;
        double volume;
        double volume_tolerance;  // relative
    };
    // The cylinder and sphere are inscribed polyhedra: slightly smaller than the solid.
    const Expect expected[] = {{"box", 2462, 1.2, 1e-12},
                               {"bar", 9730, 9.0, 1e-12},
                               {"cylinder", 21302, kPi * 0.25 * 5.0, 1e-3},
                               {"sphere", 10242, 4.0 / 3.0 * kPi, 1e-3}};
    for (const Expect& e : expected) {
        SECTION(e.name) {
            const TriangleMesh mesh = make_builtin_mesh(e.name);
            CHECK(std::abs(double(mesh.vertex_count()) - double(e.paper_vertices)) <= 0.02 * e.paper_vertices);
            require_clean_closed(mesh);
            const double volume = signed_volume(mesh.positions, mesh.triangles);
            CHECK(std::abs(volume - e.volume) <= e.volume_tolerance * e.volume);
            CHECK(volume <= e.volume * (1.0 + 1e-12));
        }
    }
}

TEST_CASE("built-in meshes have outward normals and well-shaped triangles", "[mesh][builtin]") {
    for (const std::string& name : builtin_mesh_names()) {
        const TriangleMesh mesh = make_builtin_mesh(name);
        INFO(name);
        // All four are convex and centred at the origin: outward means along the position.
        std::vector<Vec3> normals;
        vertex_normals(mesh.positions, build_vertex_rings(mesh), normals);
        std::size_t inward = 0;
        for (std::size_t v = 0; v < mesh.vertex_count(); ++v) inward += glm::dot(normals[v], mesh.positions[v]) <= 0.0;
        CHECK(inward == 0);
        double worst = 1.0;
        for (const Triangle& t : mesh.triangles)
            worst = std::min(worst, shape_quality(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]));
        CHECK(worst > 0.55);
    }
}

TEST_CASE("built-in meshes: dimensions as documented", "[mesh][builtin]") {
    auto extent = [](const char* name) { return bounding_box(make_builtin_mesh(name).positions).extent(); };
    CHECK(extent("box").x == Approx(1.0));
    CHECK(extent("box").z == Approx(1.2));
    CHECK(extent("bar").y == Approx(1.0));
    CHECK(extent("bar").z == Approx(9.0));
    CHECK(extent("cylinder").x == Approx(1.0));
    CHECK(extent("cylinder").z == Approx(5.0));
    CHECK(extent("sphere").y == Approx(2.0));
    const BoundingBox bar = bounding_box(make_builtin_mesh("bar").positions);
    CHECK(glm::length(bar.centre()) < 1e-12);
}

TEST_CASE("built-in meshes at other resolutions stay closed and manifold", "[mesh][builtin]") {
    const std::pair<const char*, int> cases[] = {{"box", 1}, {"box", 4}, {"bar", 2}, {"cylinder", 3},
                                                 {"cylinder", 7}, {"cylinder", 24}, {"sphere", 1}, {"sphere", 3}};
    for (const auto& [name, resolution] : cases) {
        INFO(name << ":" << resolution);
        require_clean_closed(make_builtin_mesh(name, resolution));
    }
    CHECK(make_builtin_mesh("box", 10).vertex_count() < make_builtin_mesh("box", 11).vertex_count());
    CHECK(make_builtin_mesh("sphere", 2).vertex_count() == 162);
}

TEST_CASE("built-in meshes reject unknown names and resolutions out of range", "[mesh][builtin]") {
    CHECK_THROWS_AS(make_builtin_mesh("torus"), InputError);
    CHECK_THROWS_AS(make_builtin_mesh("box", -1), InputError);
    CHECK_THROWS_AS(make_builtin_mesh("sphere", 40), InputError);
    CHECK_THROWS_AS(make_builtin_mesh("cylinder", 2), InputError);
    CHECK(builtin_mesh_names().size() == 4);
}

TEST_CASE("midpoint subdivision keeps the surface, closed and manifold, with V + E vertices and 4 F triangles",
          "[mesh][subdivision]") {
    for (const char* name : {"box", "cylinder", "sphere"}) {
        INFO(name);
        const TriangleMesh coarse = make_builtin_mesh(name, name == std::string("sphere") ? 2 : 6);
        const TriangleMesh fine = subdivide_midpoints(coarse);
        // Euler: a closed triangle mesh has E = 3F/2 edges.
        CHECK(fine.vertex_count() == coarse.vertex_count() + 3 * coarse.triangle_count() / 2);
        CHECK(fine.triangle_count() == 4 * coarse.triangle_count());
        require_clean_closed(fine);
        // The new vertices lie on the old edges, so the enclosed volume is unchanged.
        const double before = signed_volume(coarse.positions, coarse.triangles);
        CHECK(signed_volume(fine.positions, fine.triangles) == Approx(before).epsilon(1e-12));
        for (std::size_t v = 0; v < coarse.vertex_count(); ++v) CHECK(fine.positions[v] == coarse.positions[v]);
    }
    // A placement of the new vertex: onto the unit sphere, as the icosphere places them.
    const auto on_sphere = [](const Vec3& a, const Vec3& b) { return glm::normalize(a + b); };
    const TriangleMesh sphere = subdivide_midpoints(make_builtin_mesh("sphere", 1), on_sphere);
    const TriangleMesh level2 = make_builtin_mesh("sphere", 2);
    REQUIRE(sphere.vertex_count() == level2.vertex_count());
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) CHECK(glm::length(sphere.positions[v] - level2.positions[v]) < 1e-15);
}

TEST_CASE("refining some triangles keeps the mesh closed, conforming and in place, whatever the winding",
          "[mesh][refine]") {
    std::mt19937 random(14);
    for (const char* name : {"box", "cylinder", "sphere"}) {
        TriangleMesh coarse = make_builtin_mesh(name, name == std::string("sphere") ? 2 : 6);
        coarse.scalar.resize(coarse.vertex_count());
        for (double& s : coarse.scalar) s = std::uniform_real_distribution<double>(0.0, 1.0)(random);
        for (int trial = 0; trial < 5; ++trial) {
            std::vector<std::uint32_t> asked;
            for (std::uint32_t t = 0; t < coarse.triangle_count(); ++t)
                if (random() % 10 == 0) asked.push_back(t);
            INFO(name << ", " << asked.size() << " triangles asked");
            const RefinedMesh refined = refine_triangles(coarse, asked);
            const TriangleMesh& fine = refined.mesh;
            require_clean_closed(fine);
            CHECK(signed_volume(fine.positions, fine.triangles) ==
                  Approx(signed_volume(coarse.positions, coarse.triangles)).epsilon(1e-12));
            const std::size_t old = coarse.vertex_count();
            REQUIRE(fine.vertex_count() == old + refined.parents.size());
            for (std::size_t v = 0; v < old; ++v) CHECK(fine.positions[v] == coarse.positions[v]);
            // Each new vertex is its edge's midpoint, with the mean of its scalar.
            std::set<std::pair<std::uint32_t, std::uint32_t>> split;
            for (std::size_t k = 0; k < refined.parents.size(); ++k) {
                const auto [a, b] = refined.parents[k];
                CHECK(a < b);
                CHECK(fine.positions[old + k] == 0.5 * (coarse.positions[a] + coarse.positions[b]));
                CHECK(fine.scalar[old + k] == 0.5 * (coarse.scalar[a] + coarse.scalar[b]));
                split.insert({a, b});
            }
            const auto is_split = [&](std::uint32_t a, std::uint32_t b) {
                return split.count({std::min(a, b), std::max(a, b)}) > 0;
            };
            // Every edge of an asked triangle is split; no triangle has exactly two
            // split edges; each triangle becomes 1, 2 or 4.
            for (std::uint32_t t : asked)
                for (int k = 0; k < 3; ++k) CHECK(is_split(coarse.triangles[t][k], coarse.triangles[t][(k + 1) % 3]));
            std::size_t expected = 0;
            for (const Triangle& t : coarse.triangles) {
                const int marked = is_split(t[0], t[1]) + is_split(t[1], t[2]) + is_split(t[2], t[0]);
                CHECK(marked != 2);
                expected += marked == 0 ? 1 : marked == 1 ? 2 : 4;
            }
            CHECK(fine.triangle_count() == expected);

            // The mirrored winding refines the same way: same vertices, same numbering.
            TriangleMesh flipped = coarse;
            for (Triangle& t : flipped.triangles) std::swap(t.y, t.z);
            const RefinedMesh mirror = refine_triangles(flipped, asked);
            CHECK(mirror.parents == refined.parents);
            CHECK(mirror.mesh.positions == fine.positions);
            CHECK(mirror.mesh.triangle_count() == fine.triangle_count());
        }
        // Asking for every triangle is one level of midpoint subdivision, numbered by edge.
        std::vector<std::uint32_t> all(coarse.triangle_count());
        for (std::uint32_t t = 0; t < all.size(); ++t) all[t] = t;
        const TriangleMesh everywhere = refine_triangles(coarse, all).mesh;
        const TriangleMesh subdivided = subdivide_midpoints(coarse);
        REQUIRE(everywhere.vertex_count() == subdivided.vertex_count());
        CHECK(everywhere.triangle_count() == subdivided.triangle_count());
        std::vector<Vec3> a = everywhere.positions, b = subdivided.positions;
        const auto less = [](const Vec3& p, const Vec3& q) {
            return std::tie(p.x, p.y, p.z) < std::tie(q.x, q.y, q.z);
        };
        std::sort(a.begin(), a.end(), less);
        std::sort(b.begin(), b.end(), less);
        CHECK(a == b);
    }
}
