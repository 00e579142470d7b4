#pragma once
// Meshes with known geodesic distances for the region tests: a flat grid, an
// icosphere, an open tube and a capped cylinder (all generated, none read from disk).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>

#include "mesh/triangle_mesh.h"

namespace vfsd::test {

// A flat n x n grid of quads over [0, size]^2 in the z = 0 plane, each quad split
// along the same diagonal. Vertex (i, j) has index j * (n + 1) + i.
inline TriangleMesh grid_mesh(int n, double size) {
    TriangleMesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.positions.push_back(Vec3(size * i / n, size * j / n, 0.0));
    auto at = [n](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    return m;
}

// An icosahedron subdivided `levels` times and projected onto the sphere of `radius`
// about the origin (10 * 4^levels + 2 vertices).
inline TriangleMesh icosphere(int levels, double radius) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    TriangleMesh m;
    const double p[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                             {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& q : p) m.positions.push_back(glm::normalize(Vec3(q[0], q[1], q[2])));
    m.triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                   {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                   {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            m.positions.push_back(glm::normalize(m.positions[a] + m.positions[b]));
            const auto id = static_cast<std::uint32_t>(m.positions.size() - 1);
            mid.emplace(key, id);
            return id;
        };
        std::vector<Triangle> next;
        for (const Triangle& f : m.triangles) {
            const std::uint32_t a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
            next.insert(next.end(), {{f[0], a, c}, {f[1], b, a}, {f[2], c, b}, {a, b, c}});
        }
        m.triangles.swap(next);
    }
    for (Vec3& q : m.positions) q *= radius;
    return m;
}

// A tube of `radius` along z from z = 0 to `height`: `around` vertices per ring,
// `rings` + 1 rings; vertex (k, j) (angle index k, ring j) has index j * around + k.
// With `capped`, each end is closed by a fan around a centre vertex (the last two).
inline TriangleMesh cylinder_mesh(int around, int rings, double radius, double height, bool capped) {
    TriangleMesh m;
    const double pi = 3.14159265358979323846;
    for (int j = 0; j <= rings; ++j)
        for (int k = 0; k < around; ++k) {
            const double a = 2.0 * pi * k / around;
            m.positions.push_back(Vec3(radius * std::cos(a), radius * std::sin(a), height * j / rings));
        }
    auto at = [around](int k, int j) { return static_cast<std::uint32_t>(j * around + (k % around)); };
    for (int j = 0; j < rings; ++j)
        for (int k = 0; k < around; ++k) {
            m.triangles.push_back({at(k, j), at(k + 1, j), at(k + 1, j + 1)});
            m.triangles.push_back({at(k, j), at(k + 1, j + 1), at(k, j + 1)});
        }
    if (capped) {
        const auto bottom = static_cast<std::uint32_t>(m.positions.size());
        m.positions.push_back(Vec3(0.0, 0.0, 0.0));
        m.positions.push_back(Vec3(0.0, 0.0, height));
        for (int k = 0; k < around; ++k) {
            m.triangles.push_back({bottom, at(k + 1, 0), at(k, 0)});
            m.triangles.push_back({bottom + 1, at(k, rings), at(k + 1, rings)});
        }
    }
    return m;
}

}  // namespace vfsd::test
