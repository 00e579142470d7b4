// The curve follows a repainted inner region: it starts at the region's centroid,
// leaves along the region's axis, and keeps its shape (docs/desktop.md).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "curve/curve_on_region.h"
#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "mesh/vertex_rings.h"

using namespace vfsd;

namespace {

struct Bar {
    TriangleMesh mesh = make_builtin_mesh("bar", 4);  // 1 x 1 x 9, z in [-4.5, 4.5]
    std::vector<Vec3> normals;
    std::vector<double> s;
    // Inner: the end beyond `from` along `direction`; blend over the next 2 units.
    Bar(const Vec3& direction, double from) {
        vertex_normals(mesh.positions, build_vertex_rings(mesh), normals);
        for (const Vec3& p : mesh.positions) s.push_back(std::clamp((from - glm::dot(p, direction)) / 2.0, 0.0, 1.0));
    }
};

const std::vector<Vec3> kCurve = {{5, 5, 5}, {6, 5, 5}, {7, 6, 5}, {7, 7, 6}, {7, 8, 7}, {6, 9, 7}, {5, 9, 8}};

double largest_distance_change(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < a.size(); ++j)
            worst = std::max(worst, std::abs(glm::length(a[i] - a[j]) - glm::length(b[i] - b[j])));
    return worst;
}

}  // namespace

TEST_CASE("the curve starts at the inner region's centroid, leaves along its axis, keeps its shape", "[curve]") {
    for (const Vec3& direction : {Vec3(0, 0, 1), Vec3(0, 0, -1)}) {
        const Bar bar(direction, 2.5);
        const std::vector<Vec3> placed = curve_on_region(kCurve, bar.mesh.positions, bar.normals, bar.s);
        Vec3 centroid(0.0);
        int count = 0;
        for (std::size_t v = 0; v < bar.s.size(); ++v)
            if (bar.s[v] <= 0.0) centroid += bar.mesh.positions[v], ++count;
        centroid /= double(count);
        INFO("direction " << direction.z);
        CHECK(glm::length(placed[0] - centroid) < 1e-12);
        CHECK(glm::dot(glm::normalize(placed[1] - placed[0]), direction) > 1.0 - 1e-12);  // out of the bar's end
        CHECK(largest_distance_change(kCurve, placed) < 1e-12);
        // Placing again changes nothing.
        const std::vector<Vec3> again = curve_on_region(placed, bar.mesh.positions, bar.normals, bar.s);
        for (std::size_t i = 0; i < placed.size(); ++i) CHECK(glm::length(again[i] - placed[i]) < 1e-12);
    }
}

TEST_CASE("the curve's placement turns and moves with the mesh", "[curve][invariance]") {
    const Bar bar(Vec3(0, 0, 1), 2.5);
    const std::vector<Vec3> placed = curve_on_region(kCurve, bar.mesh.positions, bar.normals, bar.s);
    const glm::dmat3 r(glm::rotate(glm::dmat4(1.0), 1.3, glm::normalize(Vec3(0.2, -1.0, 0.4))));
    const Vec3 offset(300.0, -20.0, 7.0);
    std::vector<Vec3> moved_positions, moved_normals, moved_curve;
    for (const Vec3& p : bar.mesh.positions) moved_positions.push_back(r * p + offset);
    for (const Vec3& n : bar.normals) moved_normals.push_back(r * n);
    for (const Vec3& p : kCurve) moved_curve.push_back(r * p + offset);
    const std::vector<Vec3> moved = curve_on_region(moved_curve, moved_positions, moved_normals, bar.s);
    for (std::size_t i = 0; i < placed.size(); ++i) CHECK(glm::length(moved[i] - (r * placed[i] + offset)) < 1e-9);
}

TEST_CASE("without an inner region the curve stays; a point curve moves to the region", "[curve]") {
    const Bar bar(Vec3(0, 0, 1), 2.5);
    const std::vector<double> all_outer(bar.s.size(), 1.0);
    CHECK(curve_on_region(kCurve, bar.mesh.positions, bar.normals, all_outer) == kCurve);
    const std::vector<Vec3> point(4, Vec3(1, 2, 3));
    const std::vector<Vec3> placed = curve_on_region(point, bar.mesh.positions, bar.normals, bar.s);
    for (const Vec3& p : placed) CHECK(glm::length(p - placed[0]) == 0.0);
    CHECK(placed[0].z > 2.5);
}

TEST_CASE("turn_onto: a proper rotation taking a onto b, for b anywhere, opposite a included", "[curve]") {
    const std::vector<Vec3> directions = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.3, -0.5, 0.81}, {-0.7, 0.1, 0.2}};
    for (const Vec3& d : directions) {
        const Vec3 a = glm::normalize(d);
        const Vec3 near_opposite = glm::normalize(-a + Vec3(1e-13, -2e-13, 0.5e-13));
        const Vec3 near = glm::normalize(a + Vec3(0, 1e-9, 0)), other = glm::normalize(Vec3(0.2, 0.9, -0.4));
        for (const Vec3& b : {a, -a, near_opposite, near, other}) {
            const glm::dmat3 r = turn_onto(a, b);
            INFO("a = (" << a.x << ", " << a.y << ", " << a.z << "), b = (" << b.x << ", " << b.y << ", " << b.z
                         << ")");
            CHECK(glm::length(r * a - b) < 1e-9);
            CHECK(glm::determinant(r) == Approx(1.0).margin(1e-9));  // a turn, never a mirror image
            const glm::dmat3 identity = glm::transpose(r) * r;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) CHECK(identity[i][j] == Approx(i == j ? 1.0 : 0.0).margin(1e-9));
        }
    }
}
