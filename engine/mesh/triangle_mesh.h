#pragma once
// A triangle mesh as flat arrays: the one mesh type every part of vfsd shares.

#include <cstdint>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace vfsd {

using Vec3 = glm::dvec3;
using Triangle = glm::u32vec3;  // vertex indices, counter-clockwise seen from outside

struct TriangleMesh {
    std::vector<Vec3> positions;
    std::vector<Triangle> triangles;
    // Optional per-vertex scalar (the region field s of sec. 3); empty when absent.
    std::vector<double> scalar;

    std::size_t vertex_count() const { return positions.size(); }
    std::size_t triangle_count() const { return triangles.size(); }
    bool has_scalar() const { return scalar.size() == positions.size() && !positions.empty(); }
};

struct BoundingBox {
    Vec3 min{0.0};
    Vec3 max{0.0};
    Vec3 centre() const { return 0.5 * (min + max); }
    Vec3 extent() const { return max - min; }
    double diagonal() const;
};

}  // namespace vfsd
