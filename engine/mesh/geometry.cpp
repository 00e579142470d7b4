#include "mesh/geometry.h"

#include "base/parallel.h"

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

namespace {

Vec3 unit_or_zero(const Vec3& v) {
    const double len = glm::length(v);
    return len > 0.0 ? v / len : Vec3(0.0);
}

// ring_area_vector in scalars: glm's cross products of Vec3 temporaries went
// through the stack (store-to-load stalls), twice the time; the same operations
// in the same order, so the same bits.
inline Vec3 ring_area_sum(const Vec3* positions, const VertexRings& rings, std::uint32_t v) {
    const std::uint32_t begin = rings.offsets[v], end = rings.offsets[v + 1];
    const std::uint32_t* neighbours = rings.neighbours.data();
    const std::uint8_t* wedge = rings.wedge.data();
    const double x = positions[v].x, y = positions[v].y, z = positions[v].z;
    double sx = 0.0, sy = 0.0, sz = 0.0;
    if (begin == end) return Vec3(0.0);
    // Each neighbour loaded once: the second edge b − x of one wedge is the first of the next.
    double ax = positions[neighbours[begin]].x - x, ay = positions[neighbours[begin]].y - y,
           az = positions[neighbours[begin]].z - z;
    for (std::uint32_t i = begin; i < end; ++i) {
        const Vec3& b = positions[neighbours[i + 1 == end ? begin : i + 1]];
        const double bx = b.x - x, by = b.y - y, bz = b.z - z;
        if (wedge[i]) {
            sx += ay * bz - by * az;  // (a − x) × (b − x): twice the triangle's area times its normal
            sy += az * bx - bz * ax;
            sz += ax * by - bx * ay;
        }
        ax = bx, ay = by, az = bz;
    }
    return Vec3(sx, sy, sz);
}

}  // namespace

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
        for (auto v = static_cast<std::uint32_t>(first); v < last; ++v)
            normals[v] = unit_or_zero(ring_area_sum(positions.data(), rings, v));
    });
}

void vertex_normals(const std::vector<Vec3>& positions, const VertexRings& rings,
                    const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& normals) {
    normals.resize(positions.size());
    parallel_for(vertices.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i)
            normals[vertices[i]] = unit_or_zero(ring_area_sum(positions.data(), rings, vertices[i]));
    });
}

void vertex_normals(const std::vector<Vec3>& positions, const VertexRings& rings,
                    const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& normals,
                    std::vector<Vec3>& area_vectors) {
    normals.resize(positions.size());
    area_vectors.resize(vertices.size());
    parallel_for(vertices.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) {
            const Vec3 sum = ring_area_sum(positions.data(), rings, vertices[i]);
            area_vectors[i] = sum;
            normals[vertices[i]] = unit_or_zero(sum);
        }
    });
}

}  // namespace vfsd
