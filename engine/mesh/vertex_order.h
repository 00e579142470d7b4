#pragma once
// A vertex order with locality: breadth-first over the 1-rings, so ring
// neighbours get nearby indices whatever order the mesh file had. The
// deformation works in this order (neighbours share cache lines, and each
// thread's contiguous share of the vertices is one compact patch of the
// surface) and hands positions back in the input's order.

#include <cstdint>
#include <vector>

#include "mesh/vertex_rings.h"

namespace vfsd {

// order[i] = the input vertex that becomes vertex i; every connected piece in
// turn, each breadth-first from its lowest-numbered vertex.
std::vector<std::uint32_t> breadth_first_order(const VertexRings& rings);

// The rings of the same mesh with vertex order[i] renumbered i.
VertexRings reorder_rings(const VertexRings& rings, const std::vector<std::uint32_t>& order);

// values[order[i]] for every i.
template <class T>
std::vector<T> gather_in_order(const std::vector<T>& values, const std::vector<std::uint32_t>& order) {
    std::vector<T> out(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) out[i] = values[order[i]];
    return out;
}

}  // namespace vfsd
