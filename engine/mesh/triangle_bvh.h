#pragma once
// A bounding volume hierarchy over a mesh's triangles: the first triangle a ray
// meets in about O(log n) box tests instead of a test of every triangle (the
// editors pick the surface under the pointer every frame, on meshes of millions
// of triangles).
//
// Why our own: Debian 12 packages Embree (libembree-dev), but Embree is x86/ARM
// SIMD code that does not compile to WebAssembly, and the web editor runs this
// same engine; Debian has no other ray-query library. The design is the classic
// compact one:
//  - built once per topology, top-down, splitting the triangle centroids at the
//    best of 16 bins along their longest axis by the surface area heuristic
//    (I. Wald, "On fast construction of SAH-based bounding volume hierarchies",
//    IEEE Symposium on Interactive Ray Tracing 2007), at most 4 triangles a leaf;
//  - one flat array of nodes in depth-first order (a node's first child follows
//    it), boxes in float (32 bytes a node);
//  - refit() recomputes every box bottom-up in O(n), the leaves on parallel_for's
//    threads, when the vertices move and the triangles stay (the deformation
//    moves them every step); the tree keeps its shape, so hits stay exact and only
//    the speed suffers if the mesh moves far from where the tree was built;
//  - first_hit() returns exactly first_hit_brute_force's hit (mesh/ray_cast.h): the
//    same triangle test, the same order of hits, and box tests with a slack larger
//    than the test's rounding, so no box is skipped that holds a hit.

#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/ray_cast.h"

namespace vfsd {

struct BvhBox;  // a triangle's box while building (triangle_bvh.cpp)

class TriangleBvh {
public:
    TriangleBvh() = default;  // no triangles: no hits
    // The hierarchy of `triangles` with its boxes at `positions`.
    TriangleBvh(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles);

    // New positions of the same vertices: every box again, bottom-up.
    void refit(const std::vector<Vec3>& positions);

    // The first hit along the ray, the same as first_hit_brute_force; `positions`
    // must be those of the last build or refit.
    std::optional<RayHit> first_hit(const Ray& ray, const std::vector<Vec3>& positions) const;

    std::size_t triangle_count() const { return triangles_.size(); }
    std::size_t node_count() const { return nodes_.size(); }
    std::size_t depth() const { return depth_; }

private:
    struct Node {
        glm::vec3 lo, hi;     // the box, rounded to float (box tests allow for that)
        std::uint32_t first;  // leaf: its first triangle; inner node: its second child (the first is the next node)
        std::uint32_t count;  // leaf: how many triangles (at least 1); inner node: 0
    };
    void build_nodes(const std::vector<BvhBox>& boxes, std::vector<std::uint32_t>& order);
    void fit_leaf(Node& leaf, const std::vector<Vec3>& positions) const;

    std::vector<Node> nodes_;
    std::vector<Triangle> triangles_;           // in leaf order
    std::vector<std::uint32_t> mesh_triangle_;  // each one's index in the mesh
    double scale_ = 0.0;                        // largest |coordinate| of the root box
    std::size_t depth_ = 0;                     // nodes on the longest path from the root
};

}  // namespace vfsd
