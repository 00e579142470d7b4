#include "mesh/vertex_rings.h"

#include <algorithm>

namespace vfsd {
namespace {

// One directed wedge (a -> b) of the fan around a vertex: triangle (v, a, b).
struct Wedge {
    std::uint32_t a, b;
};

// Orders the wedges of one vertex into fans. Each fan starts at a wedge whose `a`
// is no other wedge's `b` (a boundary or non-manifold gap); what remains after all
// such fans are taken are closed cycles.
void order_fans(std::vector<Wedge>& wedges, std::vector<std::uint32_t>& ring, std::vector<std::uint8_t>& gaps) {
    std::vector<bool> used(wedges.size(), false);
    auto find_from = [&](std::uint32_t a) -> int {
        for (std::size_t i = 0; i < wedges.size(); ++i)
            if (!used[i] && wedges[i].a == a) return static_cast<int>(i);
        return -1;
    };
    auto is_fan_start = [&](std::size_t i) {
        for (std::size_t j = 0; j < wedges.size(); ++j)
            if (j != i && !used[j] && wedges[j].b == wedges[i].a) return false;
        return true;
    };
    auto walk = [&](std::size_t start) {
        std::uint32_t first = wedges[start].a;
        ring.push_back(first);
        int i = static_cast<int>(start);
        while (i >= 0) {
            used[i] = true;
            gaps.push_back(1);
            std::uint32_t b = wedges[i].b;
            if (b == first) return;  // closed cycle: b is already the first entry
            ring.push_back(b);
            i = find_from(b);
        }
        gaps.push_back(0);  // open fan: no triangle after its last neighbour
    };
    for (std::size_t i = 0; i < wedges.size(); ++i)
        if (!used[i] && is_fan_start(i)) walk(i);
    for (std::size_t i = 0; i < wedges.size(); ++i)
        if (!used[i]) walk(i);
}

}  // namespace

bool VertexRings::is_closed(std::uint32_t v) const {
    if (valence(v) == 0) return false;
    for (std::uint32_t i = begin(v); i < end(v); ++i)
        if (!wedge[i]) return false;
    return true;
}

std::uint32_t VertexRings::max_valence() const {
    std::uint32_t m = 0;
    for (std::uint32_t v = 0; v < vertex_count(); ++v) m = std::max(m, valence(v));
    return m;
}

VertexRings build_vertex_rings(const TriangleMesh& mesh) {
    const auto n = static_cast<std::uint32_t>(mesh.vertex_count());
    // Bucket the wedges of every triangle by their apex vertex (CSR, two passes).
    std::vector<std::uint32_t> start(n + 1, 0);
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) ++start[t[k] + 1];
    for (std::uint32_t v = 0; v < n; ++v) start[v + 1] += start[v];
    std::vector<Wedge> wedges(start[n]);
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) wedges[fill[t[k]]++] = {t[(k + 1) % 3], t[(k + 2) % 3]};

    VertexRings rings;
    rings.offsets.assign(n + 1, 0);
    rings.neighbours.reserve(wedges.size());
    rings.wedge.reserve(wedges.size());
    std::vector<Wedge> local;
    std::vector<std::uint32_t> ring;
    std::vector<std::uint8_t> gaps;
    for (std::uint32_t v = 0; v < n; ++v) {
        local.assign(wedges.begin() + start[v], wedges.begin() + start[v + 1]);
        ring.clear();
        gaps.clear();
        order_fans(local, ring, gaps);
        rings.neighbours.insert(rings.neighbours.end(), ring.begin(), ring.end());
        rings.wedge.insert(rings.wedge.end(), gaps.begin(), gaps.end());
        rings.offsets[v + 1] = static_cast<std::uint32_t>(rings.neighbours.size());
    }
    return rings;
}

}  // namespace vfsd
