#include "mesh/geometry.h"

#include "base/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace vfsd {

double BoundingBox::diagonal() const { return glm::length(max - min); }

BoundingBox bounding_box(const std::vector<Vec3>& positions) {
    if (positions.empty()) return {};
    BoundingBox box{Vec3(std::numeric_limits<double>::infinity()), Vec3(-std::numeric_limits<double>::infinity())};
    for (const Vec3& p : positions) {
        box.min = glm::min(box.min, p);
        box.max = glm::max(box.max, p);
    }
    return box;
}

double centred_diameter(const std::vector<Vec3>& positions) {
    if (positions.empty()) return 0.0;
    Vec3 mean(0.0);
    for (const Vec3& p : positions) mean += p;
    mean /= double(positions.size());
    double largest = 0.0;
    for (const Vec3& p : positions) largest = std::max(largest, glm::length(p - mean));
    return 2.0 * largest;
}

double signed_volume(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles) {
    // Sec. 7.2: sum over triangles of det(p0, p1, p2) / 6 (tetrahedron with the origin).
    double six_volume = 0.0;
    for (const Triangle& t : triangles)
        six_volume += glm::dot(positions[t[0]], glm::cross(positions[t[1]], positions[t[2]]));
    return six_volume / 6.0;
}

double signed_volume(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles, const Vec3& origin) {
    double six_volume = 0.0;
    for (const Triangle& t : triangles)
        six_volume += glm::dot(positions[t[0]] - origin, glm::cross(positions[t[1]] - origin, positions[t[2]] - origin));
    return six_volume / 6.0;
}

// In scalars: glm's Vec3 temporaries went through the stack.
double six_volume(const Vec3* p, const Triangle& t, const Vec3& c) {
    const Vec3 &a = p[t.x], &b = p[t.y], &d = p[t.z];
    const double ax = a.x - c.x, ay = a.y - c.y, az = a.z - c.z;
    const double bx = b.x - c.x, by = b.y - c.y, bz = b.z - c.z, dx = d.x - c.x, dy = d.y - c.y, dz = d.z - c.z;
    return ax * (by * dz - dy * bz) + ay * (bz * dx - dz * bx) + az * (bx * dy - dx * by);
}

namespace {

// Four doubles side by side: SIMD lanes (two simd128 vectors in WebAssembly).
using VolumeLanes = double __attribute__((vector_size(4 * sizeof(double))));

// out = corner `corner` of triangles t[0 .. 3], coordinate `axis`, less the centre's, in lanes.
[[gnu::always_inline]] inline void corner_lanes(const Vec3* p, const Triangle* t, int corner, int axis, double centre,
                                                VolumeLanes& out) {
    out = VolumeLanes{p[t[0][corner]][axis], p[t[1][corner]][axis], p[t[2][corner]][axis], p[t[3][corner]][axis]} -
          centre;
}

}  // namespace

// Four triangles at a time, triangle i in lane i mod 4, the last ones into lane
// 0. Each lane's operations are six_volume's in its order, with no fused
// multiply-add.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
__attribute__((target_clones("avx2", "default")))
#endif
double
six_volume_block(const Vec3* p, const Triangle* t, std::size_t count, const Vec3& c) {
    VolumeLanes sum = {0.0, 0.0, 0.0, 0.0};
    std::size_t i = 0;
    for (; i + 4 <= count; i += 4) {
        VolumeLanes ax, ay, az, bx, by, bz, dx, dy, dz;
        corner_lanes(p, t + i, 0, 0, c.x, ax), corner_lanes(p, t + i, 0, 1, c.y, ay),
            corner_lanes(p, t + i, 0, 2, c.z, az);
        corner_lanes(p, t + i, 1, 0, c.x, bx), corner_lanes(p, t + i, 1, 1, c.y, by),
            corner_lanes(p, t + i, 1, 2, c.z, bz);
        corner_lanes(p, t + i, 2, 0, c.x, dx), corner_lanes(p, t + i, 2, 1, c.y, dy),
            corner_lanes(p, t + i, 2, 2, c.z, dz);
        sum += ax * (by * dz - dy * bz) + ay * (bz * dx - dz * bx) + az * (bx * dy - dx * by);
    }
    double first = sum[0];
    for (; i < count; ++i) first += six_volume(p, t[i], c);
    return (first + sum[1]) + (sum[2] + sum[3]);
}

namespace {

Vec3 unit_or_zero(const Vec3& v) {
    const double len = glm::length(v);
    return len > 0.0 ? v / len : Vec3(0.0);
}

// ring_area_vector in scalars: glm's cross products of Vec3 temporaries went
// through the stack (store-to-load stalls), twice the time; the same operations
// in the same order, so the same bits. Over the ring's `size` neighbours from
// ring[0], with size a constant where with_ring_size makes it one.
template <class Size>
[[gnu::always_inline]] inline Vec3 wedge_sum(const Vec3* positions, const std::uint32_t* ring,
                                             const std::uint8_t* wedge, const Vec3& centre, Size size) {
    const double x = centre.x, y = centre.y, z = centre.z;
    const std::uint32_t n = size;
    double sx = 0.0, sy = 0.0, sz = 0.0;
    // Each neighbour loaded once: the second edge b − x of one wedge is the first of the next.
    double ax = positions[ring[0]].x - x, ay = positions[ring[0]].y - y, az = positions[ring[0]].z - z;
#pragma GCC unroll 8
    for (std::uint32_t i = 0; i < n; ++i) {
        const Vec3& b = positions[ring[i + 1 == n ? 0 : i + 1]];
        const double bx = b.x - x, by = b.y - y, bz = b.z - z;
        // (a − x) × (b − x): twice the triangle's area times its normal; −0 where the
        // wedge is open (x + (−0) is x, bit for bit, for every x), so no branch.
        const bool closed = wedge[i];
        sx += closed ? ay * bz - by * az : -0.0;
        sy += closed ? az * bx - bz * ax : -0.0;
        sz += closed ? ax * by - bx * ay : -0.0;
        ax = bx, ay = by, az = bz;
    }
    return Vec3(sx, sy, sz);
}

[[gnu::always_inline]] inline Vec3 ring_area_sum(const Vec3* positions, const VertexRings& rings, std::uint32_t v) {
    const std::uint32_t begin = rings.offsets[v], size = rings.offsets[v + 1] - begin;
    if (size == 0) return Vec3(0.0);
    const std::uint32_t* ring = rings.neighbours.data() + begin;
    const std::uint8_t* wedge = rings.wedge.data() + begin;
    return with_ring_size(size, [&](auto n) { return wedge_sum(positions, ring, wedge, positions[v], n); });
}

constexpr int kNormalLanes = 64;

// Vertex vertex_of(i)'s unit normal into normals[vertex_of(i)] for i in
// [first, last), and its ring area vector into area_vectors[i] when asked: the
// ring sums one vertex at a time, their normalisation kNormalLanes at a time.
template <class VertexOf>
void normals_in_lanes(const Vec3* positions, const VertexRings& rings, const VertexOf& vertex_of, std::size_t first,
                      std::size_t last, Vec3* normals, Vec3* area_vectors) {
    double x[kNormalLanes], y[kNormalLanes], z[kNormalLanes];
    for (std::size_t begin = first; begin < last; begin += kNormalLanes) {
        const int n = static_cast<int>(std::min<std::size_t>(kNormalLanes, last - begin));
        for (int j = 0; j < n; ++j) {
            const Vec3 sum = ring_area_sum(positions, rings, vertex_of(begin + j));
            x[j] = sum.x, y[j] = sum.y, z[j] = sum.z;
        }
        if (area_vectors)
            for (int j = 0; j < n; ++j) area_vectors[begin + j] = Vec3(x[j], y[j], z[j]);
        normalise_lanes(n, x, y, z);
        for (int j = 0; j < n; ++j) normals[vertex_of(begin + j)] = Vec3(x[j], y[j], z[j]);
    }
}

}  // namespace

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
__attribute__((target_clones("avx2", "default")))
#endif
void normalise_lanes(int n, double* __restrict x, double* __restrict y, double* __restrict z) {
    for (int j = 0; j < n; ++j) {
        const double length = std::sqrt(x[j] * x[j] + y[j] * y[j] + z[j] * z[j]);
        const bool positive = length > 0.0;
        const double divisor = positive ? length : 1.0;  // no division by zero in the lanes not taken
        const double qx = x[j] / divisor, qy = y[j] / divisor, qz = z[j] / divisor;
        x[j] = positive ? qx : 0.0;
        y[j] = positive ? qy : 0.0;
        z[j] = positive ? qz : 0.0;
    }
}

Vec3 ring_area_vector(const std::vector<Vec3>& positions, const VertexRings& rings, std::uint32_t v) {
    return ring_area_sum(positions.data(), rings, v);
}

Vec3 vertex_normal(const std::vector<Vec3>& positions, const VertexRings& rings, std::uint32_t v) {
    return unit_or_zero(ring_area_sum(positions.data(), rings, v));
}

void ring_area_vectors(const std::vector<Vec3>& positions, const VertexRings& rings,
                       const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& area_vectors) {
    area_vectors.resize(vertices.size());
    parallel_for(vertices.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i)
            area_vectors[i] = ring_area_sum(positions.data(), rings, vertices[i]);
    });
}

void vertex_normals(const std::vector<Vec3>& positions, const VertexRings& rings, std::vector<Vec3>& normals) {
    normals.resize(positions.size());
    parallel_for(rings.vertex_count(), [&](std::size_t first, std::size_t last) {
        const auto itself = [](std::size_t i) { return static_cast<std::uint32_t>(i); };
        normals_in_lanes(positions.data(), rings, itself, first, last, normals.data(), nullptr);
    });
}

void vertex_normals(const std::vector<Vec3>& positions, const VertexRings& rings,
                    const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& normals) {
    normals.resize(positions.size());
    parallel_for(vertices.size(), [&](std::size_t first, std::size_t last) {
        const std::uint32_t* list = vertices.data();
        const auto listed = [list](std::size_t i) { return list[i]; };
        normals_in_lanes(positions.data(), rings, listed, first, last, normals.data(), nullptr);
    });
}

void vertex_normals(const std::vector<Vec3>& positions, const VertexRings& rings,
                    const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& normals,
                    std::vector<Vec3>& area_vectors) {
    normals.resize(positions.size());
    area_vectors.resize(vertices.size());
    parallel_for(vertices.size(), [&](std::size_t first, std::size_t last) {
        const std::uint32_t* list = vertices.data();
        const auto listed = [list](std::size_t i) { return list[i]; };
        normals_in_lanes(positions.data(), rings, listed, first, last, normals.data(), area_vectors.data());
    });
}

}  // namespace vfsd
