// The fold count of sec. 7's evaluation (deform/quality.h): the triangles a
// deformation turned against their edge neighbours, counted whole or in the parts
// an editor keeps between frames.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "deform/quality.h"
#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "test_fold_support.h"

using namespace vfsd;

namespace {

bool shares_edge(const Triangle& a, const Triangle& b) {
    int shared = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) shared += a[i] == b[j];
    return shared == 2;
}

}  // namespace

TEST_CASE("every triangle's neighbours are the triangles sharing one of its edges", "[quality]") {
    const TriangleMesh sphere = make_builtin_mesh("sphere", 2);
    const TriangleNeighbours n = triangle_neighbours(sphere.triangles);
    REQUIRE(n.offsets.size() == sphere.triangles.size() + 1);
    for (std::uint32_t t = 0; t < sphere.triangles.size(); ++t) {
        REQUIRE(n.offsets[t + 1] - n.offsets[t] == 3);  // closed and manifold: one across each edge
        for (std::uint32_t k = n.offsets[t]; k < n.offsets[t + 1]; ++k) {
            const std::uint32_t u = n.list[k];
            CHECK(shares_edge(sphere.triangles[t], sphere.triangles[u]));
            const auto back = std::find(n.list.begin() + n.offsets[u], n.list.begin() + n.offsets[u + 1], t);
            CHECK(back != n.list.begin() + n.offsets[u + 1]);  // symmetric
        }
    }
    // An edge shared by three triangles (non-manifold) gives each the other two.
    const std::vector<Triangle> fan = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    const TriangleNeighbours f = triangle_neighbours(fan);
    for (std::uint32_t t = 0; t < 3; ++t) CHECK(f.offsets[t + 1] - f.offsets[t] == 2);
}

TEST_CASE("the fold count finds the triangles a deformation turned over, and only those", "[quality]") {
    const TriangleMesh sphere = make_builtin_mesh("sphere", 3);
    std::mt19937 random(7);
    std::uniform_int_distribution<std::size_t> pick(0, sphere.positions.size() - 1);
    for (int trial = 0; trial < 20; ++trial) {
        // Slide one vertex past a neighbour, along the surface: triangles of its fan turn over.
        std::vector<Vec3> after = sphere.positions;
        const std::uint32_t v = static_cast<std::uint32_t>(pick(random));
        const Triangle& fan = *std::find_if(sphere.triangles.begin(), sphere.triangles.end(),
                                            [&](const Triangle& t) { return t[0] == v || t[1] == v || t[2] == v; });
        const std::uint32_t a = fan[0] == v ? fan[1] : fan[0];
        after[v] = sphere.positions[a] + 0.7 * (sphere.positions[a] - sphere.positions[v]);
        const std::vector<std::uint32_t> folded = flipped_triangle_list(sphere.positions, after, sphere.triangles);
        REQUIRE(!folded.empty());
        for (const std::uint32_t t : folded) {
            const Triangle& tri = sphere.triangles[t];
            CHECK((tri[0] == v || tri[1] == v || tri[2] == v));
        }
        // In parts, as the editor counts: the same triangles.
        const TriangleNeighbours n = triangle_neighbours(sphere.triangles);
        CHECK(newly_facing_against(facing_against_neighbours(sphere.positions, sphere.triangles, n),
                                   facing_against_neighbours(after, sphere.triangles, n)) == folded);
        // Folded before and after is no new fold.
        CHECK(flipped_triangle_list(after, after, sphere.triangles).empty());
    }
    // A rigid motion and a uniform scale fold nothing.
    std::vector<Vec3> moved = sphere.positions;
    for (Vec3& p : moved) p = 3.0 * Vec3(-p.y, p.x, p.z) + Vec3(10.0, -4.0, 2.0);
    CHECK(flipped_triangle_list(sphere.positions, moved, sphere.triangles).empty());
}

namespace {

// x ↦ A x + t: a rotation times stretches of σ and 1/σ along random axes (volume kept).
std::vector<Vec3> stretched(const std::vector<Vec3>& x, double sigma, std::mt19937& random) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const auto axis = [&] { return glm::normalize(Vec3(unit(random), unit(random), unit(random)) + Vec3(1e-9)); };
    const glm::dmat3 turn(glm::rotate(glm::dmat4(1.0), 3.0 * unit(random), axis()));
    const glm::dmat3 frame(glm::rotate(glm::dmat4(1.0), 3.0 * unit(random), axis()));
    const glm::dmat3 a = turn * frame * glm::dmat3(sigma, 0, 0, 0, 1.0 / sigma, 0, 0, 0, 1.0) * glm::transpose(frame);
    const Vec3 t(unit(random), unit(random), unit(random));
    std::vector<Vec3> out;
    for (const Vec3& p : x) out.push_back(a * p + 100.0 * t);
    return out;
}

}  // namespace

TEST_CASE("no affine map reverses a triangle, however rough the mesh", "[quality]") {
    std::mt19937 random(10);
    std::size_t tipped = 0;  // what the neighbour measure counts under the same maps
    for (int trial = 0; trial < 12; ++trial) {
        const TriangleMesh mesh = test::rough_sphere(0.05 * (trial % 4), random);
        const double sigma = 1.0 + 0.5 * (trial % 5);  // up to 3
        const std::vector<Vec3> after = stretched(mesh.positions, sigma, random);
        INFO("trial " << trial << ", stretch " << sigma);
        CHECK(reversed_triangle_list(mesh.positions, after, mesh.triangles).empty());
        tipped += count_flipped_triangles(mesh.positions, after, mesh.triangles);
    }
    // Not a property of the new measure: the reason it exists. The rough spheres'
    // bumps tip past their neighbours' mean under the stronger stretches (dozens
    // of them over these maps).
    INFO("the neighbour measure counted " << tipped << " triangles");
    CHECK(tipped > 0);
}

TEST_CASE("a smooth twist reverses no triangle of a fine mesh", "[quality]") {
    const TriangleMesh mesh = make_builtin_mesh("cylinder", 48);
    const BoundingBox box = bounding_box(mesh.positions);
    std::vector<Vec3> after;
    for (const Vec3& p : mesh.positions) {  // half a turn from the bottom to the top
        const double angle = 3.14159265358979 * (p.z - box.min.z) / (box.max.z - box.min.z);
        after.push_back(
            Vec3(std::cos(angle) * p.x - std::sin(angle) * p.y, std::sin(angle) * p.x + std::cos(angle) * p.y, p.z));
    }
    CHECK(reversed_triangle_list(mesh.positions, after, mesh.triangles).empty());
}

TEST_CASE("a vertex pushed past its ring reverses triangles around it, a small move none", "[quality]") {
    const TriangleMesh mesh = make_builtin_mesh("sphere", 3);
    std::mt19937 random(3);
    for (int trial = 0; trial < 10; ++trial) {
        const Triangle& picked = mesh.triangles[random() % mesh.triangles.size()];
        const std::uint32_t v = picked[0], w = picked[1];  // an edge v–w
        const Vec3 across = mesh.positions[w] - mesh.positions[v];
        std::vector<Vec3> after = mesh.positions;
        after[v] = mesh.positions[w] + 0.5 * across;  // past its neighbour w, along the surface
        const std::vector<std::uint32_t> reversed = reversed_triangle_list(mesh.positions, after, mesh.triangles);
        REQUIRE(!reversed.empty());
        for (const std::uint32_t t : reversed) {
            const Triangle& tri = mesh.triangles[t];
            CHECK((tri[0] == v || tri[1] == v || tri[2] == v));
        }
        after[v] = mesh.positions[v] + 0.1 * across;  // a tenth of the edge: nothing turns
        CHECK(reversed_triangle_list(mesh.positions, after, mesh.triangles).empty());
    }
}

TEST_CASE("the fold test's normals in lanes are unit_normal's, bit for bit, degenerate triangles too", "[quality]") {
    // Random corners, some triangles with repeated or collinear corners (length
    // 0) and a non-finite one: unit_normals must give exactly what unit_normal
    // gives each, over any range and block boundary.
    std::mt19937 random(17);
    std::uniform_real_distribution<double> coordinate(-3.0, 3.0);
    std::vector<Vec3> x(300);
    for (Vec3& p : x) p = Vec3(coordinate(random), coordinate(random), coordinate(random));
    x[7] = x[8];
    x[9] = 0.5 * (x[10] + x[11]);
    x[12].y = std::nan("");
    std::vector<Triangle> triangles;
    std::uniform_int_distribution<std::uint32_t> vertex(0, 299);
    for (int i = 0; i < 1000; ++i) triangles.push_back(Triangle(vertex(random), vertex(random), vertex(random)));
    triangles[3] = Triangle(7, 8, 20), triangles[64] = Triangle(9, 10, 11), triangles[65] = Triangle(5, 5, 6);
    triangles[130] = Triangle(12, 1, 2);
    std::vector<Vec3> lanes(triangles.size(), Vec3(-1.0));
    unit_normals(x, triangles, 1, 999, lanes);
    CHECK(lanes[0] == Vec3(-1.0));  // outside the range: untouched
    CHECK(lanes[999] == Vec3(-1.0));
    int mismatched = 0, degenerate = 0;
    for (std::size_t t = 1; t < 999; ++t) {
        const Vec3 one = unit_normal(x, triangles[t]);
        degenerate += one == Vec3(0.0);
        for (int k = 0; k < 3; ++k) mismatched += std::memcmp(&one[k], &lanes[t][k], sizeof(double)) != 0;
    }
    CHECK(mismatched == 0);
    CHECK(degenerate >= 4);
}
