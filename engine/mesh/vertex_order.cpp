#include "mesh/vertex_order.h"

namespace vfsd {

std::vector<std::uint32_t> breadth_first_order(const VertexRings& rings) {
    const std::size_t n = rings.vertex_count();
    std::vector<std::uint32_t> order;
    order.reserve(n);
    std::vector<std::uint8_t> queued(n, 0);
    for (std::uint32_t seed = 0; seed < n; ++seed) {
        if (queued[seed]) continue;
        queued[seed] = 1;
        order.push_back(seed);
        for (std::size_t head = order.size() - 1; head < order.size(); ++head) {
            const std::uint32_t v = order[head];
            for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
                const std::uint32_t y = rings.neighbours[k];
                if (!queued[y]) queued[y] = 1, order.push_back(y);
            }
        }
    }
    return order;
}

VertexRings reorder_rings(const VertexRings& rings, const std::vector<std::uint32_t>& order) {
    std::vector<std::uint32_t> rank(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) rank[order[i]] = static_cast<std::uint32_t>(i);
    VertexRings out;
    out.offsets.reserve(rings.offsets.size());
    out.neighbours.reserve(rings.neighbours.size());
    out.wedge.reserve(rings.wedge.size());
    out.offsets.push_back(0);
    for (const std::uint32_t v : order) {
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
            out.neighbours.push_back(rank[rings.neighbours[k]]);
            out.wedge.push_back(rings.wedge[k]);
        }
        out.offsets.push_back(static_cast<std::uint32_t>(out.neighbours.size()));
    }
    return out;
}

}  // namespace vfsd
