#pragma once
// Index-based 1-ring adjacency in compressed-sparse-row form.
//
// The neighbours of vertex v are neighbours[offsets[v] .. offsets[v+1]), ordered
// counter-clockwise around v (seen from outside, i.e. consistent with the triangle
// winding). Consecutive neighbours a = ring[k], b = ring[k+1 mod valence] span the
// triangle (v, a, b) exactly when wedge[offsets[v] + k] is 1. A closed ring has a
// wedge after every neighbour; an open ring (boundary vertex) has one gap after its
// last neighbour; a non-manifold vertex has one gap per fan, and a closed fan among
// several is written with its first neighbour repeated at its end (so the ring
// can be longer than the number of distinct neighbours). Any valence is allowed.

#include <cstdint>
#include <type_traits>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace vfsd {

struct VertexRings {
    std::vector<std::uint32_t> offsets;     // vertex_count + 1 entries
    std::vector<std::uint32_t> neighbours;  // ordered 1-rings, concatenated
    std::vector<std::uint8_t> wedge;        // 1 if a triangle follows the neighbour in its ring

    std::size_t vertex_count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
    std::uint32_t begin(std::uint32_t v) const { return offsets[v]; }
    std::uint32_t end(std::uint32_t v) const { return offsets[v + 1]; }
    std::uint32_t valence(std::uint32_t v) const { return offsets[v + 1] - offsets[v]; }
    // Index in `neighbours` of the ring entry after entry i of vertex v (cyclic).
    std::uint32_t next(std::uint32_t v, std::uint32_t i) const { return i + 1 == end(v) ? begin(v) : i + 1; }
    // True when every wedge of v is present: v is an interior manifold vertex.
    bool is_closed(std::uint32_t v) const;
    std::uint32_t max_valence() const;
};

// Calls visit(size) with `size` a compile-time constant (std::integral_constant)
// for the valences most rings have, 5 to 7, and as the ring's size otherwise:
// a loop over a ring of constant size is unrolled. A loop whose trip count
// varies from vertex to vertex is ended by a branch that the predictor misses
// on nearly every ring of an irregular mesh: the smoothing took more than
// twice as long on the armadillo (docs/benchmarks.md, "Rings unrolled by valence").
template <class Visit>
[[gnu::always_inline]] inline auto with_ring_size(std::uint32_t size, const Visit& visit) {
    if (size == 6) return visit(std::integral_constant<std::uint32_t, 6>{});
    if (size == 5) return visit(std::integral_constant<std::uint32_t, 5>{});
    if (size == 7) return visit(std::integral_constant<std::uint32_t, 7>{});
    return visit(size);
}

// Builds the ordered rings. Handles boundaries, isolated vertices (valence 0) and
// non-manifold configurations (each fan becomes a run of the ring).
VertexRings build_vertex_rings(const TriangleMesh& mesh);

}  // namespace vfsd
