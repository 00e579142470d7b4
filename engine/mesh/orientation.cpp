#include "mesh/orientation.h"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace vfsd {
namespace {

// Every triangle's three sides (the edge and which way the triangle runs it),
// bucketed by the edge's lower vertex: a counting sort, linear in the mesh,
// whose buckets hold a handful of sides each.
class EdgeSides {
public:
    explicit EdgeSides(const std::vector<Triangle>& triangles) {
        std::uint32_t n = 0;
        for (const Triangle& t : triangles) n = std::max({n, t[0] + 1, t[1] + 1, t[2] + 1});
        offsets_.assign(n + 1, 0);
        for (const Triangle& t : triangles)
            for (int k = 0; k < 3; ++k) ++offsets_[std::min(t[k], t[(k + 1) % 3]) + 1];
        for (std::uint32_t v = 0; v < n; ++v) offsets_[v + 1] += offsets_[v];
        sides_.resize(offsets_[n]);
        std::vector<std::uint32_t> filled(offsets_.begin(), offsets_.end() - 1);
        for (std::uint32_t i = 0; i < triangles.size(); ++i)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = triangles[i][k], b = triangles[i][(k + 1) % 3];
                sides_[filled[std::min(a, b)]++] = {std::max(a, b), i, a < b};
            }
    }
    // The one other triangle on edge a → b of triangle t, and whether it runs
    // the edge the same way; false unless exactly two triangles share the edge.
    bool across(std::uint32_t t, std::uint32_t a, std::uint32_t b, std::uint32_t& other, bool& same_way) const {
        const std::uint32_t low = std::min(a, b), high = std::max(a, b);
        int found = 0;
        for (std::uint32_t k = offsets_[low]; k < offsets_[low + 1]; ++k) {
            const Side& side = sides_[k];
            if (side.high != high || side.triangle == t) continue;
            ++found, other = side.triangle, same_way = side.forward == (a < b);
        }
        return found == 1;
    }

private:
    struct Side {
        std::uint32_t high, triangle;
        bool forward;  // the triangle runs the edge from its lower vertex to its higher
    };
    std::vector<std::uint32_t> offsets_;
    std::vector<Side> sides_;
};

}  // namespace

std::size_t orient_consistently(std::vector<Triangle>& triangles) {
    const EdgeSides sides(triangles);
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
            for (int k = 0; k < 3; ++k) {
                std::uint32_t n = 0;
                bool same_way = false;
                if (!sides.across(t, triangles[t][k], triangles[t][(k + 1) % 3], n, same_way) || turn[n] != kUnset)
                    continue;
                turn[n] = turn[t] ^ std::uint8_t(same_way);
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
