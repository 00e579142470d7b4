// Drawn boundaries: trace closed surface polylines across the mesh, cut the edges they
// cross, flood-fill the seed's side (figs. 2a, 9-11 of the paper).
#include "region/boundary_cut.h"

#include <algorithm>
#include <limits>
#include <string>

#include "base/error.h"

namespace vfsd {
namespace {

constexpr std::uint32_t kNone = ~0u;

// Index of b in a's ring, or kNone.
std::uint32_t ring_entry(const VertexRings& rings, std::uint32_t a, std::uint32_t b) {
    for (std::uint32_t i = rings.begin(a); i < rings.end(a); ++i)
        if (rings.neighbours[i] == b) return i;
    return kNone;
}

// The mesh as the tracer needs it: which triangle holds each directed ring edge a -> b,
// and the cut parity of each ring entry (kept equal for a -> b and b -> a).
struct CutState {
    const std::vector<Vec3>& p;
    const std::vector<Triangle>& tris;
    const VertexRings& rings;
    std::vector<std::uint32_t> triangle_of_entry;
    std::vector<std::uint8_t> cut;
    std::vector<std::uint8_t> visited;  // triangles a loop passes through
};

CutState make_state(const std::vector<Vec3>& p, const std::vector<Triangle>& tris, const VertexRings& rings) {
    CutState s{p, tris, rings, std::vector<std::uint32_t>(rings.neighbours.size(), kNone),
               std::vector<std::uint8_t>(rings.neighbours.size(), 0), std::vector<std::uint8_t>(tris.size(), 0)};
    for (std::uint32_t f = 0; f < tris.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t e = ring_entry(rings, tris[f][k], tris[f][(k + 1) % 3]);
            if (e != kNone) s.triangle_of_entry[e] = f;
        }
    return s;
}

// A point nudged off the vertices and edges of its triangle, so walks never pass
// exactly through a vertex.
Vec3 nudge(Vec3 b) { return (1.0 - 1e-9) * b + Vec3(1e-9 / 3.0); }

// Barycentric direction (summing to 0) of the 3D vector d projected into triangle c.
Vec3 barycentric_direction(const Vec3 c[3], const Vec3& d) {
    const Vec3 e1 = c[1] - c[0], e2 = c[2] - c[0];
    const double a = glm::dot(e1, e1), b = glm::dot(e1, e2), e = glm::dot(e2, e2);
    const double det = a * e - b * b;
    if (det <= 0.0) return Vec3(0.0);
    const double r1 = glm::dot(e1, d), r2 = glm::dot(e2, d);
    const double d1 = (e * r1 - b * r2) / det, d2 = (a * r2 - b * r1) / det;
    return Vec3(-d1 - d2, d1, d2);
}

// Crosses the edge opposite corner k of triangle f at barycentric point b: toggles its
// cut parity and moves (f, b, entered) into the neighbouring triangle. False at a
// mesh boundary.
bool cross_edge(CutState& s, std::uint32_t& f, Vec3& b, int k, int& entered) {
    const std::uint32_t u = s.tris[f][(k + 1) % 3], w = s.tris[f][(k + 2) % 3];
    const std::uint32_t uw = ring_entry(s.rings, u, w), wu = ring_entry(s.rings, w, u);
    if (uw == kNone || wu == kNone || s.triangle_of_entry[wu] == kNone) return false;
    s.cut[uw] ^= 1;
    s.cut[wu] ^= 1;
    const double bu = b[(k + 1) % 3], bw = b[(k + 2) % 3];
    f = s.triangle_of_entry[wu];
    for (int j = 0; j < 3; ++j) {
        const std::uint32_t v = s.tris[f][j];
        b[j] = v == u ? bu : v == w ? bw : 0.0;
        if (v != u && v != w) entered = j;
    }
    b /= b.x + b.y + b.z;
    return true;
}

// Walks straight from (f, b) to the point `target` in triangle `target_f`.
bool trace_segment(CutState& s, std::uint32_t f, Vec3 b, std::uint32_t target_f, const Vec3& target) {
    int entered = -1;
    for (std::size_t step = 0; step <= s.tris.size(); ++step) {
        s.visited[f] = 1;
        if (f == target_f) return true;
        const Vec3 c[3] = {s.p[s.tris[f][0]], s.p[s.tris[f][1]], s.p[s.tris[f][2]]};
        const Vec3 x = b.x * c[0] + b.y * c[1] + b.z * c[2];
        const Vec3 delta = barycentric_direction(c, target - x);
        // Leave by the edge the direction reaches first (not the one just entered).
        int exit = -1;
        double t_exit = std::numeric_limits<double>::infinity();
        for (int k = 0; k < 3; ++k)
            if (k != entered && delta[k] < 0.0 && -b[k] / delta[k] < t_exit) t_exit = -b[k] / delta[k], exit = k;
        if (exit < 0) return false;
        b = glm::max(b + t_exit * delta, Vec3(0.0));
        b[exit] = 0.0;
        if (!cross_edge(s, f, b, exit, entered)) return false;
    }
    return false;
}

void trace_loop(CutState& s, SurfaceLoop loop, std::size_t index) {
    const std::string name = "boundary loop " + std::to_string(index);
    for (const SurfacePoint& q : loop) check_surface_point(q, s.tris.size(), name.c_str());
    if (loop.size() > 1 && loop.front().triangle == loop.back().triangle &&
        glm::length(loop.front().barycentric - loop.back().barycentric) < 1e-12)
        loop.pop_back();  // an explicitly repeated first point
    if (loop.size() < 3) throw InputError(name + ": a closed loop needs at least 3 points");
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const SurfacePoint& a = loop[i];
        const SurfacePoint& b = loop[(i + 1) % loop.size()];
        SurfacePoint target{b.triangle, nudge(b.barycentric)};
        if (!trace_segment(s, a.triangle, nudge(a.barycentric), b.triangle, surface_position(s.p, s.tris, target)))
            throw InputError(name + ": cannot trace the surface from point " + std::to_string(i) + " to point " +
                             std::to_string((i + 1) % loop.size()) +
                             (i + 1 == loop.size() ? " (the loop does not close)" : "") +
                             ": they must lie a few triangles apart on one connected, unbroken part of the surface");
    }
}

// Vertices reachable from `start`, crossing only edges whose entry is not in `cut`
// (pass an empty `cut` to ignore cuts). Returns the count.
std::size_t flood(const VertexRings& rings, std::uint32_t start, const std::vector<std::uint8_t>& cut,
                  std::vector<std::uint8_t>& mask) {
    mask.assign(rings.vertex_count(), 0);
    std::vector<std::uint32_t> stack{start};
    mask[start] = 1;
    std::size_t count = 1;
    while (!stack.empty()) {
        const std::uint32_t v = stack.back();
        stack.pop_back();
        for (std::uint32_t i = rings.begin(v); i < rings.end(v); ++i) {
            const std::uint32_t w = rings.neighbours[i];
            if (mask[w] || (!cut.empty() && cut[i])) continue;
            mask[w] = 1;
            ++count;
            stack.push_back(w);
        }
    }
    return count;
}

// The vertex the seed's side grows from: the seed's vertex, or a corner of its triangle
// when no loop passes through that triangle.
std::uint32_t seed_vertex(const CutState& s, const SurfacePoint& seed) {
    for (int k = 0; k < 3; ++k)
        if (seed.barycentric[k] >= 1.0 - 1e-12) return s.tris[seed.triangle][k];
    if (s.visited[seed.triangle])
        throw InputError("boundary loops: the seed lies in a triangle a loop passes through; move it off the loop");
    return s.tris[seed.triangle][0];
}

}  // namespace

std::vector<std::uint8_t> seed_side_of_loops(const std::vector<Vec3>& positions,
                                             const std::vector<Triangle>& triangles, const VertexRings& rings,
                                             const std::vector<SurfaceLoop>& loops, const SurfacePoint& seed) {
    if (rings.vertex_count() != positions.size())
        throw InputError("boundary loops: positions and rings disagree on the vertex count");
    check_surface_point(seed, triangles.size(), "boundary seed");
    CutState s = make_state(positions, triangles, rings);
    for (std::size_t i = 0; i < loops.size(); ++i) trace_loop(s, loops[i], i);
    const std::uint32_t start = seed_vertex(s, seed);
    std::vector<std::uint8_t> side, component;
    const std::size_t reached = flood(rings, start, s.cut, side);
    if (reached == flood(rings, start, {}, component))
        throw InputError("boundary loops: the loops do not separate the surface around the seed "
                         "(its side is the whole connected part of the mesh)");
    return side;
}

LoopRegions regions_from_loops(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                               const VertexRings& rings, const SurfaceLoop& inner_loop,
                               const SurfaceLoop& outer_loop, const SurfacePoint& seed) {
    LoopRegions r;
    r.inner = seed_side_of_loops(positions, triangles, rings, {inner_loop}, seed);
    std::vector<std::uint8_t> near_outer = seed_side_of_loops(positions, triangles, rings, {outer_loop}, seed);
    std::size_t between = 0;
    for (std::size_t v = 0; v < near_outer.size(); ++v) {
        if (r.inner[v] && !near_outer[v])
            throw InputError("boundary loops: the inner loop must lie between the seed and the outer loop "
                             "(the loops cross or are swapped)");
        between += near_outer[v] && !r.inner[v];
    }
    if (between == 0) throw InputError("boundary loops: no intermediate region lies between the two loops");
    r.outer.resize(near_outer.size());
    for (std::size_t v = 0; v < near_outer.size(); ++v) r.outer[v] = near_outer[v] ? 0 : 1;
    return r;
}

}  // namespace vfsd
