#include "mesh/orientation.h"

#include <algorithm>
#include <cstdint>
#include <tuple>
#include <utility>

namespace vfsd {
namespace {

// One side of an undirected edge (low, high): the triangle and whether it runs
// low → high.
struct EdgeSide {
    std::uint32_t low, high, triangle;
    bool forward;
};

// Per triangle, the triangles across its edges of exactly two triangles, each
// with whether the two run the edge the same way (one must turn to agree).
struct TurnGraph {
    std::vector<std::uint32_t> offsets, neighbours;
    std::vector<std::uint8_t> same_way;
};

TurnGraph turn_graph(const std::vector<Triangle>& triangles) {
    std::vector<EdgeSide> sides;
    sides.reserve(3 * triangles.size());
    for (std::uint32_t t = 0; t < triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = triangles[t][k], b = triangles[t][(k + 1) % 3];
            sides.push_back({std::min(a, b), std::max(a, b), t, a < b});
        }
    std::sort(sides.begin(), sides.end(), [](const EdgeSide& x, const EdgeSide& y) {
        return std::tie(x.low, x.high, x.triangle) < std::tie(y.low, y.high, y.triangle);
    });
    std::vector<std::pair<std::size_t, std::size_t>> links;  // (this side, the other side), indices into sides
    for (std::size_t i = 0; i < sides.size();) {
        std::size_t j = i;
        while (j < sides.size() && sides[j].low == sides[i].low && sides[j].high == sides[i].high) ++j;
        if (j - i == 2) links.emplace_back(i, i + 1), links.emplace_back(i + 1, i);
        i = j;
    }
    TurnGraph g;
    g.offsets.assign(triangles.size() + 1, 0);
    for (const auto& link : links) ++g.offsets[sides[link.first].triangle + 1];
    for (std::size_t t = 0; t < triangles.size(); ++t) g.offsets[t + 1] += g.offsets[t];
    g.neighbours.resize(links.size());
    g.same_way.resize(links.size());
    std::vector<std::uint32_t> filled(g.offsets.begin(), g.offsets.end() - 1);
    for (const auto& [this_side, other_side] : links) {
        const EdgeSide &here = sides[this_side], &there = sides[other_side];
        const std::uint32_t k = filled[here.triangle]++;
        g.neighbours[k] = there.triangle;
        g.same_way[k] = here.forward == there.forward;
    }
    return g;
}

}  // namespace

std::size_t orient_consistently(std::vector<Triangle>& triangles) {
    const TurnGraph g = turn_graph(triangles);
    constexpr std::uint8_t kUnset = 2;
    std::vector<std::uint8_t> turn(triangles.size(), kUnset);  // relative to its part's first triangle
    std::vector<std::uint32_t> part;
    std::size_t turned = 0;
    for (std::uint32_t first = 0; first < triangles.size(); ++first) {
        if (turn[first] != kUnset) continue;
        part.assign(1, first);
        turn[first] = 0;
        std::size_t turns = 0;
        for (std::size_t i = 0; i < part.size(); ++i) {
            const std::uint32_t t = part[i];
            for (std::uint32_t k = g.offsets[t]; k < g.offsets[t + 1]; ++k) {
                const std::uint32_t n = g.neighbours[k];
                if (turn[n] != kUnset) continue;
                turn[n] = turn[t] ^ g.same_way[k];
                turns += turn[n];
                part.push_back(n);
            }
        }
        const std::uint8_t keep = 2 * turns > part.size();  // most of the part was wound the other way
        for (const std::uint32_t t : part)
            if (turn[t] != keep) std::swap(triangles[t][1], triangles[t][2]), ++turned;
    }
    return turned;
}

}  // namespace vfsd
