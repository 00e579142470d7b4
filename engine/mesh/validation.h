#pragma once
// Validation of a triangle mesh before deformation: index and coordinate sanity,
// manifoldness, orientation consistency, boundaries and valence.
//
// The deformation of the paper needs a closed, consistently oriented 2-manifold for
// its volume statement (sec. 7.2) and well-defined 1-rings for its gradients; this
// report says whether a mesh is one and, if not, exactly where it is not.
// Runs in O(n log n) time and O(n) memory for n triangles.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace vfsd {

struct ValidationReport {
    // A directed edge; for boundary edges the direction is the one it has in its triangle.
    struct Edge {
        std::uint32_t from, to;
    };

    std::size_t vertex_count = 0;
    std::size_t triangle_count = 0;

    // Problems of the input arrays (all lists are sorted and hold indices).
    std::vector<std::uint32_t> out_of_range_triangles;  // a vertex index >= vertex_count
    std::vector<std::uint32_t> non_finite_vertices;     // a coordinate is NaN or infinite
    std::vector<std::uint32_t> degenerate_triangles;    // a repeated index, or zero area
    std::vector<std::uint32_t> duplicate_triangles;     // same vertex set as an earlier triangle
    std::vector<std::uint32_t> isolated_vertices;       // in no triangle

    // Topology. Triangles with an out-of-range or repeated index take no part.
    // Non-manifold edges: used by more than two triangles, or by two triangles that
    // traverse it in the same direction (inconsistent orientation); as (min, max).
    std::vector<Edge> non_manifold_edges;
    // Vertices whose triangles form more than one fan (edge-connected through edges
    // with exactly two triangles). The ends of an edge with more than two triangles
    // are among them.
    std::vector<std::uint32_t> non_manifold_vertices;
    std::vector<Edge> boundary_edges;  // edges of exactly one triangle
    // Boundary edges chained into loops of vertices, each in the direction of its
    // triangles' edges (counter-clockwise around the hole's complement, seen from
    // outside). A chain that cannot close (only at non-manifold vertices) is listed too.
    std::vector<std::vector<std::uint32_t>> boundary_loops;

    // Valence = number of distinct edge neighbours; histogram[k] = vertices of valence k.
    std::uint32_t valence_min = 0;
    std::uint32_t valence_max = 0;
    std::vector<std::size_t> valence_histogram;

    // Closed: at least one usable triangle and no boundary edge.
    bool is_closed = false;
    // Manifold: no non-manifold edge or vertex, no duplicate triangle, no repeated or
    // out-of-range index. `reasons` says why not, one line per kind of problem.
    bool is_manifold = false;
    std::vector<std::string> reasons;
    // Problems that do not break manifoldness: zero-area triangles, isolated
    // vertices, non-finite coordinates.
    std::vector<std::string> warnings;
};

ValidationReport validate_mesh(const TriangleMesh& mesh);

// Chains directed edges into loops: each loop follows an edge (a, b) with an unused
// edge starting at b until it returns to its first vertex or finds none.
std::vector<std::vector<std::uint32_t>> chain_boundary_loops(const std::vector<ValidationReport::Edge>& edges,
                                                             std::size_t vertex_count);

}  // namespace vfsd
