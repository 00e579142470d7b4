#pragma once
// Rays against triangles: the one ray–triangle test every ray query in vfsd uses
// (editor picking, the hierarchy of mesh/triangle_bvh.h), and the loop over all
// triangles that any faster search must agree with exactly.
//
// T. Möller, B. Trumbore, "Fast, minimum storage ray/triangle intersection",
// Journal of Graphics Tools 2(1), 1997.

#include <cstdint>
#include <optional>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace vfsd {

struct Ray {
    Vec3 origin{0.0};
    Vec3 direction{0.0, 0.0, -1.0};  // unit length for picking (any length works)
};

struct RayHit {
    std::uint32_t triangle = 0;
    double u = 0.0, v = 0.0;  // barycentric weights of corners 1 and 2 (corner 0: 1 - u - v)
    double t = 0.0;           // the hit is origin + t·direction
};

// Where the ray meets triangle `index` with corners (a, b, c), either side facing,
// at t > 0. None when it misses, runs in the triangle's plane (or within about
// 1e-9 rad of it), or the triangle is degenerate or has a non-finite corner.
std::optional<RayHit> intersect_triangle(const Ray& ray, const Vec3& a, const Vec3& b, const Vec3& c,
                                         std::uint32_t index);

// The order of hits along a ray: nearer first, at equal t the lower triangle index,
// so that every way of finding the first hit finds the same one.
inline bool comes_before(const RayHit& a, const RayHit& b) {
    return a.t < b.t || (a.t == b.t && a.triangle < b.triangle);
}

// Keeps the first of `best` and `hit`.
inline void keep_first(std::optional<RayHit>& best, const std::optional<RayHit>& hit) {
    if (hit && (!best || comes_before(*hit, *best))) best = hit;
}

// The first hit, testing every triangle: the reference for TriangleBvh::first_hit.
std::optional<RayHit> first_hit_brute_force(const Ray& ray, const std::vector<Vec3>& positions,
                                            const std::vector<Triangle>& triangles);

}  // namespace vfsd
