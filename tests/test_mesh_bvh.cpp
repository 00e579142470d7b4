// The bounding volume hierarchy finds exactly the hit the loop over all triangles
// finds (the same triangle, barycentrics and distance, or no hit): for random rays
// from outside and inside, on deformed meshes, after refits, for rays through
// vertices and along edges and faces, with degenerate, duplicated and non-finite
// triangles, and on an empty mesh.

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "mesh/ray_cast.h"
#include "mesh/triangle_bvh.h"

using namespace vfsd;

namespace {

std::string describe(const std::optional<RayHit>& h) {
    if (!h) return "no hit";
    char text[160];
    std::snprintf(text, sizeof text, "triangle %u u %.17g v %.17g t %.17g", h->triangle, h->u, h->v, h->t);
    return text;
}

// Checks that the hierarchy and the loop agree bit for bit on every ray; returns how many hit.
std::size_t check_rays(const TriangleBvh& bvh, const std::vector<Vec3>& positions,
                       const std::vector<Triangle>& triangles, const std::vector<Ray>& rays) {
    std::size_t hits = 0;
    for (const Ray& ray : rays) {
        const auto expected = first_hit_brute_force(ray, positions, triangles);
        const auto got = bvh.first_hit(ray, positions);
        INFO("ray from (" << ray.origin.x << ", " << ray.origin.y << ", " << ray.origin.z << ") along ("
                          << ray.direction.x << ", " << ray.direction.y << ", " << ray.direction.z << ")");
        REQUIRE(describe(got) == describe(expected));
        hits += expected.has_value();
    }
    return hits;
}

Vec3 random_unit(std::mt19937& random) {
    std::normal_distribution<double> normal;
    const Vec3 v(normal(random), normal(random), normal(random));
    return glm::normalize(v);
}

Vec3 random_in_box(std::mt19937& random, const BoundingBox& box) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    return box.min + Vec3(unit(random), unit(random), unit(random)) * box.extent();
}

// Rays from a sphere around the mesh toward random points of its box (most hit).
std::vector<Ray> rays_from_outside(const std::vector<Vec3>& positions, int count, unsigned seed) {
    std::mt19937 random(seed);
    const BoundingBox box = bounding_box(positions);
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        const Vec3 origin = box.centre() + 1.5 * box.diagonal() * random_unit(random);
        rays.push_back({origin, glm::normalize(random_in_box(random, box) - origin)});
    }
    return rays;
}

// Rays from random points of the mesh's box in random directions.
std::vector<Ray> rays_from_inside(const std::vector<Vec3>& positions, int count, unsigned seed) {
    std::mt19937 random(seed);
    const BoundingBox box = bounding_box(positions);
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) rays.push_back({random_in_box(random, box), random_unit(random)});
    return rays;
}

// Rays from outside exactly through vertices and points of edges.
std::vector<Ray> rays_through_vertices_and_edges(const TriangleMesh& mesh, int count, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_int_distribution<std::size_t> pick(0, mesh.triangle_count() - 1);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const BoundingBox box = bounding_box(mesh.positions);
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        const Triangle& t = mesh.triangles[pick(random)];
        const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]];
        const Vec3 target = i % 2 == 0 ? a : a + unit(random) * (b - a);
        const Vec3 origin = box.centre() + 1.5 * box.diagonal() * random_unit(random);
        rays.push_back({origin, glm::normalize(target - origin)});
    }
    return rays;
}

// Every vertex moved by up to `amount` in each coordinate.
std::vector<Vec3> perturbed(std::vector<Vec3> positions, double amount, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> offset(-amount, amount);
    for (Vec3& p : positions) p += Vec3(offset(random), offset(random), offset(random));
    return positions;
}

// A large deformation: a twist about z by up to a half turn, then a bend along x.
std::vector<Vec3> twisted_and_bent(std::vector<Vec3> positions) {
    for (Vec3& p : positions) {
        const double angle = 1.5 * p.z, c = std::cos(angle), s = std::sin(angle);
        p = Vec3(c * p.x - s * p.y + 0.4 * p.z * p.z, s * p.x + c * p.y, p.z);
    }
    return positions;
}

}  // namespace

TEST_CASE("BVH: random rays meet the same triangle as the loop over all", "[mesh][bvh]") {
    const TriangleMesh mesh = make_builtin_mesh("sphere", 5);
    const TriangleBvh bvh(mesh.positions, mesh.triangles);
    CHECK(bvh.triangle_count() == mesh.triangle_count());
    CHECK(check_rays(bvh, mesh.positions, mesh.triangles, rays_from_outside(mesh.positions, 1500, 1)) > 1000);
    CHECK(check_rays(bvh, mesh.positions, mesh.triangles, rays_from_inside(mesh.positions, 1000, 2)) > 500);
}

TEST_CASE("BVH: rays through vertices, along edges and in the planes of faces", "[mesh][bvh]") {
    // The box's faces lie in the coordinate planes: axis-parallel rays run along them.
    for (const std::string name : {"sphere", "box", "cylinder"}) {
        const TriangleMesh mesh = make_builtin_mesh(name, name == "sphere" ? 4 : 0);
        INFO(name);
        const TriangleBvh bvh(mesh.positions, mesh.triangles);
        check_rays(bvh, mesh.positions, mesh.triangles, rays_through_vertices_and_edges(mesh, 1000, 3));
        std::vector<Ray> along_axes;
        for (std::size_t v = 0; v < mesh.vertex_count(); v += 7)
            for (int axis = 0; axis < 3; ++axis) {
                Vec3 d(0.0);
                d[axis] = v % 2 ? 1.0 : -1.0;
                along_axes.push_back({mesh.positions[v] - 3.0 * d, d});
            }
        check_rays(bvh, mesh.positions, mesh.triangles, along_axes);
    }
}

TEST_CASE("BVH: a perturbed mesh, and a refit after a large deformation", "[mesh][bvh]") {
    const TriangleMesh mesh = make_builtin_mesh("bar", 8);
    const std::vector<Vec3> rough = perturbed(mesh.positions, 0.04, 4);
    const TriangleBvh built(rough, mesh.triangles);
    check_rays(built, rough, mesh.triangles, rays_from_outside(rough, 1000, 5));
    check_rays(built, rough, mesh.triangles, rays_from_inside(rough, 500, 6));

    // Built on the rest shape, refit to the deformed one (and back).
    TriangleBvh refit(mesh.positions, mesh.triangles);
    const std::vector<Vec3> bent = twisted_and_bent(mesh.positions);
    refit.refit(bent);
    check_rays(refit, bent, mesh.triangles, rays_from_outside(bent, 1000, 7));
    check_rays(refit, bent, mesh.triangles, rays_from_inside(bent, 500, 8));
    refit.refit(mesh.positions);
    check_rays(refit, mesh.positions, mesh.triangles, rays_from_outside(mesh.positions, 500, 9));
}

TEST_CASE("BVH: degenerate, duplicated and non-finite triangles", "[mesh][bvh]") {
    const TriangleMesh sphere = make_builtin_mesh("sphere", 3);
    TriangleMesh mesh = sphere;
    const auto n = static_cast<std::uint32_t>(mesh.vertex_count());
    // Zero area: a repeated corner, three points on a line; a triangle twice over
    // (the lower index wins the tie); a corner at NaN and one at infinity.
    mesh.positions.push_back(Vec3(0.0, 0.0, 1.5));
    mesh.positions.push_back(Vec3(0.0, 0.0, -1.5));
    mesh.positions.push_back(Vec3(std::nan(""), 0.0, 0.0));
    mesh.positions.push_back(Vec3(std::numeric_limits<double>::infinity(), 0.0, 0.0));
    mesh.triangles.push_back({0, 0, 1});
    mesh.triangles.push_back({n, n + 1, n});
    mesh.triangles.insert(mesh.triangles.begin() + 5, mesh.triangles[40]);
    mesh.triangles.push_back(mesh.triangles[7]);
    mesh.triangles.push_back({0, 1, n + 2});
    mesh.triangles.push_back({2, 3, n + 3});
    const TriangleBvh bvh(mesh.positions, mesh.triangles);
    check_rays(bvh, mesh.positions, mesh.triangles, rays_from_outside(sphere.positions, 1000, 10));
    check_rays(bvh, mesh.positions, mesh.triangles, rays_through_vertices_and_edges(sphere, 1000, 11));
}

TEST_CASE("BVH: coincident triangles tie by the lower index", "[mesh][bvh]") {
    const std::vector<Vec3> positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const std::vector<Triangle> triangles = {{0, 1, 2}, {1, 2, 0}, {0, 1, 2}, {2, 0, 1}};
    const TriangleBvh bvh(positions, triangles);
    const Ray ray{{0.25, 0.25, 1.0}, {0.0, 0.0, -1.0}};
    const auto hit = bvh.first_hit(ray, positions);
    REQUIRE(hit);
    CHECK(hit->triangle == 0);
    CHECK(describe(hit) == describe(first_hit_brute_force(ray, positions, triangles)));
}

TEST_CASE("BVH: an empty mesh has no hits", "[mesh][bvh]") {
    const TriangleBvh empty(std::vector<Vec3>{}, std::vector<Triangle>{});
    CHECK(empty.node_count() == 0);
    CHECK_FALSE(empty.first_hit({{0, 0, 1}, {0, 0, -1}}, {}));
    CHECK_FALSE(TriangleBvh().first_hit({{0, 0, 1}, {0, 0, -1}}, {}));
}

TEST_CASE("BVH: shallow and small for a large mesh", "[mesh][bvh]") {
    const TriangleMesh mesh = make_builtin_mesh("sphere", 6);
    const TriangleBvh bvh(mesh.positions, mesh.triangles);
    CHECK(bvh.depth() < 40);
    CHECK(bvh.node_count() < mesh.triangle_count());
}
