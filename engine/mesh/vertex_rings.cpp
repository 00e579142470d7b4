#include "mesh/vertex_rings.h"

#include <algorithm>

namespace vfsd {
namespace {

// One directed wedge (a -> b) of the fan around a vertex: triangle (v, a, b).
struct Wedge {
    std::uint32_t a, b;
};

// One fan around a vertex: consecutive neighbours, each pair spanning a triangle.
struct Fan {
    std::vector<std::uint32_t> neighbours;
    bool closed = false;  // the last neighbour connects back to the first
};

// Splits the wedges of one vertex into fans. A fan starts at a wedge whose `a` is
// no other wedge's `b` (a boundary or non-manifold gap); the wedges left after all
// such fans are taken form closed cycles.
std::vector<Fan> collect_fans(const std::vector<Wedge>& wedges) {
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
        Fan fan;
        fan.neighbours.push_back(wedges[start].a);
        for (int i = static_cast<int>(start); i >= 0; i = find_from(fan.neighbours.back())) {
            used[i] = true;
            if (wedges[i].b == fan.neighbours.front()) {
                fan.closed = true;
                break;
            }
            fan.neighbours.push_back(wedges[i].b);
        }
        return fan;
    };
    std::vector<Fan> fans;
    for (std::size_t i = 0; i < wedges.size(); ++i)
        if (!used[i] && is_fan_start(i)) fans.push_back(walk(i));
    for (std::size_t i = 0; i < wedges.size(); ++i)
        if (!used[i]) fans.push_back(walk(i));
    return fans;
}

// Writes the fans as one ring. A single closed fan is the ring of an interior
// manifold vertex. With several fans each is written as an open run (a closed one
// with its first neighbour repeated at the end), so that "a wedge follows entry k"
// always means the triangle (v, ring[k], ring[k+1]).
void append_ring(const std::vector<Fan>& fans, std::vector<std::uint32_t>& ring, std::vector<std::uint8_t>& wedge) {
    const bool single_cycle = fans.size() == 1 && fans[0].closed;
    for (const Fan& fan : fans) {
        ring.insert(ring.end(), fan.neighbours.begin(), fan.neighbours.end());
        wedge.insert(wedge.end(), fan.neighbours.size() - 1, 1);
        if (single_cycle) {
            wedge.push_back(1);
        } else if (fan.closed) {
            wedge.push_back(1);
            ring.push_back(fan.neighbours.front());
            wedge.push_back(0);
        } else {
            wedge.push_back(0);
        }
    }
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
    for (std::uint32_t v = 0; v < n; ++v) {
        local.assign(wedges.begin() + start[v], wedges.begin() + start[v + 1]);
        append_ring(collect_fans(local), rings.neighbours, rings.wedge);
        rings.offsets[v + 1] = static_cast<std::uint32_t>(rings.neighbours.size());
    }
    return rings;
}

}  // namespace vfsd
