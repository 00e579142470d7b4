#pragma once
// Small generated meshes for the tests: a cube, open grids and annuli, a mesh
// whose vertices have every valence from 3 to 20, and two spheres touching at a
// vertex.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "curve/bezier_curve.h"

#include "mesh/builtin_meshes.h"
#include "mesh/triangle_mesh.h"

namespace vfsd::fixtures {

// The unit cube [-0.5, 0.5]^3: 8 vertices, 12 outward triangles.
inline TriangleMesh cube() {
    TriangleMesh m = make_builtin_mesh("box", 1);  // 1 x 1 x 1.2, one cell per face
    for (Vec3& p : m.positions) p.z /= 1.2;
    return m;
}

// An open nx x ny grid of unit quads in the plane z = 0, counter-clockwise seen
// from +z: (nx+1)(ny+1) vertices, one boundary loop of 2(nx+ny) edges.
inline TriangleMesh grid(std::uint32_t nx, std::uint32_t ny) {
    TriangleMesh m;
    for (std::uint32_t j = 0; j <= ny; ++j)
        for (std::uint32_t i = 0; i <= nx; ++i) m.positions.push_back(Vec3(i, j, 0.0));
    auto at = [&](std::uint32_t i, std::uint32_t j) { return j * (nx + 1) + i; };
    for (std::uint32_t j = 0; j < ny; ++j) {
        for (std::uint32_t i = 0; i < nx; ++i) {
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
    return m;
}

// A planar annulus of `rings` + 1 concentric rings of `around` vertices (radii 1
// to 1 + rings), counter-clockwise seen from +z: two boundary loops of `around` edges.
inline TriangleMesh annulus(std::uint32_t around, std::uint32_t rings) {
    TriangleMesh m;
    for (std::uint32_t r = 0; r <= rings; ++r) {
        for (std::uint32_t i = 0; i < around; ++i) {
            const double t = 2.0 * 3.14159265358979323846 * i / around;
            m.positions.push_back(Vec3((1.0 + r) * std::cos(t), (1.0 + r) * std::sin(t), 0.0));
        }
    }
    auto at = [&](std::uint32_t i, std::uint32_t r) { return r * around + i % around; };
    for (std::uint32_t r = 0; r < rings; ++r) {
        for (std::uint32_t i = 0; i < around; ++i) {
            m.triangles.push_back({at(i, r), at(i + 1, r), at(i + 1, r + 1)});
            m.triangles.push_back({at(i, r), at(i + 1, r + 1), at(i, r + 1)});
        }
    }
    return m;
}

// Disjoint pieces covering valences 3 to 20: for each k in [3, 20] a closed
// bipyramid over a k-gon (two apexes of valence k, a rim of valence 4) and an open
// cone over a k-gon (an interior apex of valence k, a boundary rim of valence 3).
inline TriangleMesh valence_zoo() {
    TriangleMesh m;
    for (std::uint32_t k = 3; k <= 20; ++k) {
        for (int closed = 0; closed < 2; ++closed) {
            const Vec3 centre(3.0 * k, 3.0 * closed, 0.0);
            const auto rim = static_cast<std::uint32_t>(m.positions.size());
            for (std::uint32_t i = 0; i < k; ++i) {
                const double t = 2.0 * 3.14159265358979323846 * i / k;
                m.positions.push_back(centre + Vec3(std::cos(t), std::sin(t), 0.1 * (i % 3)));
            }
            const auto top = static_cast<std::uint32_t>(m.positions.size());
            m.positions.push_back(centre + Vec3(0.0, 0.0, 1.0));
            for (std::uint32_t i = 0; i < k; ++i) m.triangles.push_back({top, rim + i, rim + (i + 1) % k});
            if (!closed) continue;
            const auto bottom = static_cast<std::uint32_t>(m.positions.size());
            m.positions.push_back(centre + Vec3(0.0, 0.0, -1.0));
            for (std::uint32_t i = 0; i < k; ++i) m.triangles.push_back({bottom, rim + (i + 1) % k, rim + i});
        }
    }
    return m;
}

// Two spheres, the second turned at random and scaled by 0.4 to 0.8, on top of
// the first and touching it at one vertex, welded there: a closed surface with
// a pinched vertex (two closed fans), as real meshes have where parts touch.
inline TriangleMesh pinched_spheres(std::mt19937& random) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    TriangleMesh mesh = make_builtin_mesh("sphere", 3);
    const TriangleMesh other = make_builtin_mesh("sphere", 2);
    const Vec3 axis =
        glm::normalize(Vec3(unit(random) - 0.5, unit(random) - 0.5, unit(random) - 0.5) + Vec3(0, 0, 1e-3));
    const glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), 6.283185307179586 * unit(random), axis);
    const double scale = 0.4 + 0.4 * unit(random);
    std::vector<Vec3> placed;
    for (const Vec3& p : other.positions) placed.push_back(scale * Vec3(turn * glm::dvec4(p, 1.0)));
    const auto by_height = [](const Vec3& a, const Vec3& b) { return a.z < b.z; };
    const auto highest = static_cast<std::uint32_t>(
        std::max_element(mesh.positions.begin(), mesh.positions.end(), by_height) - mesh.positions.begin());
    const auto lowest =
        static_cast<std::uint32_t>(std::min_element(placed.begin(), placed.end(), by_height) - placed.begin());
    const Vec3 shift = mesh.positions[highest] - placed[lowest];
    std::vector<std::uint32_t> index(placed.size());
    for (std::uint32_t v = 0; v < placed.size(); ++v) {
        index[v] = v == lowest ? highest : static_cast<std::uint32_t>(mesh.positions.size());
        if (v != lowest) mesh.positions.push_back(placed[v] + shift);
    }
    for (const Triangle& t : other.triangles) mesh.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
    return mesh;
}

// s on pinched_spheres: 0 on the upper sphere's top third, 1 on the lower
// sphere below z = 0.6, linear in height between (across the pinch at z = 1).
inline std::vector<double> pinched_spheres_field(const TriangleMesh& m) {
    double top = -1e30;
    for (const Vec3& p : m.positions) top = std::max(top, p.z);
    const double inner = top - 0.3 * (top - 1.0);
    std::vector<double> s;
    for (const Vec3& p : m.positions) s.push_back(std::clamp((inner - p.z) / (inner - 0.6), 0.0, 1.0));
    return s;
}

// A curve from the top of pinched_spheres up and to the side.
inline BezierCurve pinched_spheres_curve(const TriangleMesh& m) {
    double top = -1e30;
    for (const Vec3& p : m.positions) top = std::max(top, p.z);
    return BezierCurve({{0, 0, top}, {0, 0, top + 0.3}, {0.3, 0.1, top + 0.6}, {0.7, 0.2, top + 0.7}});
}

}  // namespace vfsd::fixtures
