#include "region/region_field.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <glm/geometric.hpp>

#include "base/error.h"
#include "base/parallel.h"

namespace vfsd {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Connected component id of every vertex (flood fill over the 1-rings).
std::vector<std::uint32_t> component_ids(const VertexRings& rings, std::uint32_t& count) {
    const auto n = static_cast<std::uint32_t>(rings.vertex_count());
    std::vector<std::uint32_t> id(n, ~0u), stack;
    count = 0;
    for (std::uint32_t start = 0; start < n; ++start) {
        if (id[start] != ~0u) continue;
        id[start] = count;
        stack.assign(1, start);
        while (!stack.empty()) {
            const std::uint32_t v = stack.back();
            stack.pop_back();
            for (std::uint32_t i = rings.begin(v); i < rings.end(v); ++i)
                if (id[rings.neighbours[i]] == ~0u) {
                    id[rings.neighbours[i]] = count;
                    stack.push_back(rings.neighbours[i]);
                }
        }
        ++count;
    }
    return id;
}

void check_masks(std::size_t n, const std::vector<std::uint8_t>& inner, const std::vector<std::uint8_t>& outer) {
    if (inner.size() != n || outer.size() != n)
        throw InputError("region field: the inner and outer masks must have one entry per vertex (" +
                         std::to_string(n) + ")");
    std::size_t both = 0, first = 0;
    for (std::size_t v = 0; v < n; ++v)
        if (inner[v] && outer[v] && both++ == 0) first = v;
    if (both > 0)
        throw InputError("region field: " + std::to_string(both) + " vertices (first: " + std::to_string(first) +
                         ") are in both the inner and the outer region");
}

// Adds the per-component warnings of painted_region_field and sets s in components that
// lack one of the regions: only inner -> 0, neither -> 1.
void resolve_components(const VertexRings& rings, const std::vector<std::uint8_t>& inner,
                        const std::vector<std::uint8_t>& outer, RegionField& field) {
    std::uint32_t count = 0;
    const std::vector<std::uint32_t> id = component_ids(rings, count);
    std::vector<std::uint8_t> has(count, 0);  // bit 1: inner, bit 2: outer
    for (std::size_t v = 0; v < id.size(); ++v) has[id[v]] |= (inner[v] ? 1 : 0) | (outer[v] ? 2 : 0);
    std::size_t only_inner = 0, neither = 0;
    for (std::size_t v = 0; v < id.size(); ++v) {
        if (has[id[v]] == 1) field.s[v] = 0.0, ++only_inner;
        if (has[id[v]] == 0) field.s[v] = 1.0, ++neither;
    }
    if (only_inner > 0)
        field.warnings.push_back(std::to_string(only_inner) +
                                 " vertices lie in parts of the mesh with an inner but no outer region: "
                                 "they follow the inner deformation rigidly (s = 0)");
    if (neither > 0)
        field.warnings.push_back(std::to_string(neither) +
                                 " vertices lie in parts of the mesh that reach neither region: "
                                 "they are not deformed (s = 1)");
}

// A blend region thinner than kThinBlendRings tears when the inner region moves:
// says how thin, where (the inner vertex nearest an outer one) and which band
// would give it kThinBlendRings rings of the mesh's mean edge near there.
void warn_if_thin(const std::vector<Vec3>& positions, const VertexRings& rings, const std::vector<double>& gi,
                  double band, RegionField& field) {
    const int width = blend_ring_width(field.s, rings);
    if (width < 0 || width >= kThinBlendRings) return;
    double edge = 0.0, nearest = kInf;
    std::size_t edges = 0, where = 0;
    for (std::uint32_t v = 0; v < positions.size(); ++v) {
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k)
            edge += glm::length(positions[rings.neighbours[k]] - positions[v]), ++edges;
        if (field.s[v] >= 1.0 && gi[v] < nearest) nearest = gi[v], where = v;
    }
    edge = edges > 0 ? edge / double(edges) : 0.0;
    char message[320];
    std::snprintf(message, sizeof message,
                  "the blend region is only %d ring%s wide near (%g, %g, %g): the inner and outer regions nearly "
                  "touch there and the shape will tear; set a transition band (region.band) of at least %.3g",
                  width, width == 1 ? "" : "s", positions[where].x, positions[where].y, positions[where].z,
                  std::max(band, 0.0) + kThinBlendRings * edge);
    field.warnings.push_back(message);
}

// The longest edge of the rings.
double longest_edge(const std::vector<Vec3>& positions, const VertexRings& rings) {
    double longest2 = 0.0;
    for (std::uint32_t v = 0; v < rings.vertex_count(); ++v)
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
            const Vec3 e = positions[rings.neighbours[k]] - positions[v];
            longest2 = std::max(longest2, glm::dot(e, e));
        }
    return std::sqrt(longest2);
}

}  // namespace

std::vector<double> level_field_from_distance(const std::vector<double>& g, double g_min, double g_max) {
    if (!std::isfinite(g_min) || !std::isfinite(g_max) || g_min < 0.0 || !(g_min < g_max))
        throw InputError("geodesic level field: thresholds must satisfy 0 <= g_min < g_max (got g_min = " +
                         std::to_string(g_min) + ", g_max = " + std::to_string(g_max) + ")");
    // Eq. (15) with 0 and 1 exchanged, so that s = 0 (full deformation) at the seed.
    std::vector<double> s(g.size());
    for (std::size_t v = 0; v < g.size(); ++v) {
        if (g[v] <= g_min) s[v] = 0.0;
        else if (g[v] >= g_max) s[v] = 1.0;
        else s[v] = (g[v] - g_min) / (g_max - g_min);
    }
    return s;
}

std::vector<double> geodesic_level_field(const std::vector<Vec3>& positions, const VertexRings& rings,
                                         std::uint32_t seed, double g_min, double g_max,
                                         const GeodesicOptions& options) {
    if (seed >= positions.size())
        throw InputError("geodesic level field: seed vertex " + std::to_string(seed) + " out of range (mesh has " +
                         std::to_string(positions.size()) + " vertices)");
    level_field_from_distance({}, g_min, g_max);  // validate the thresholds before the work
    // Beyond g_max a distance only says "outer", so the march stops where no
    // vertex it still decides can see: the distances are 1-Lipschitz along edges
    // (each edge update bounds them) and k smoothing passes average over k rings,
    // so a vertex smoothed below g_max has no k-ring vertex farther than
    // g_max + 2k edges (the march goes two longest edges further still). Those
    // distances, and so s, are the same as from a march over the whole mesh;
    // the rest is s = 1 either way.
    GeodesicOptions near = options;
    const double reach = g_max + 2.0 * (options.smoothing_iterations + 1) * longest_edge(positions, rings);
    if (std::isfinite(reach)) near.max_distance = std::min(options.max_distance, reach);
    return level_field_from_distance(geodesic_distance(positions, rings, {seed}, near), g_min, g_max);
}

int blend_ring_width(const std::vector<double>& s, const VertexRings& rings) {
    const auto n = static_cast<std::uint32_t>(s.size());
    std::vector<int> ring(n, -1);
    std::vector<std::uint32_t> queue;
    for (std::uint32_t v = 0; v < n; ++v)
        if (s[v] <= 0.0) ring[v] = 0, queue.push_back(v);
    for (std::size_t i = 0; i < queue.size(); ++i) {
        const std::uint32_t v = queue[i];
        if (s[v] >= 1.0) return ring[v];  // breadth-first: the first outer vertex reached is the nearest
        for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k)
            if (ring[rings.neighbours[k]] < 0) ring[rings.neighbours[k]] = ring[v] + 1, queue.push_back(rings.neighbours[k]);
    }
    return -1;
}

RegionField painted_region_field(const std::vector<Vec3>& positions, const VertexRings& rings,
                                 const std::vector<std::uint8_t>& inner, const std::vector<std::uint8_t>& painted_outer,
                                 const GeodesicOptions& options, double band) {
    check_masks(positions.size(), inner, painted_outer);
    if (!(band >= 0.0) || !std::isfinite(band))
        throw InputError("painted region: band must be a finite distance >= 0 (got " + std::to_string(band) + ")");
    RegionField field;
    field.s.assign(positions.size(), 1.0);
    bool any_inner = false;
    for (std::uint8_t x : inner) any_inner = any_inner || x;
    if (!any_inner) {
        field.warnings.push_back("the inner region is empty: nothing is deformed (s = 1 everywhere)");
        return field;
    }
    GeodesicOptions full = options;
    full.max_distance = kInf;  // eq. (16) needs both distances everywhere
    std::vector<double> gi, go;
    std::vector<std::uint8_t> outer = painted_outer;
    if (band == 0.0) {
        // Without a band the outer region is the painted one, and the two
        // distances do not depend on each other: one on each thread.
        parallel_for(
            2,
            [&](std::size_t first, std::size_t last) {
                for (std::size_t k = first; k < last; ++k)
                    (k == 0 ? gi : go) = geodesic_distance_to_region(positions, rings, k == 0 ? inner : outer, full);
            },
            1);
    } else {
        gi = geodesic_distance_to_region(positions, rings, inner, full);
        // The outer region less the transition band; with no outer region
        // painted, everything beyond the band (an inner region alone blends over it).
        bool any_outer = false;
        for (std::uint8_t x : painted_outer) any_outer = any_outer || x;
        for (std::size_t v = 0; v < outer.size(); ++v) {
            if (!any_outer) outer[v] = !inner[v] && gi[v] >= band;
            if (gi[v] < band) outer[v] = 0;
        }
        go = geodesic_distance_to_region(positions, rings, outer, full);
    }
    // Eq. (16): s = g_o / (g_i + g_o) * 0 + g_i / (g_i + g_o) * 1.
    for (std::size_t v = 0; v < positions.size(); ++v) {
        if (inner[v]) field.s[v] = 0.0;
        else if (outer[v]) field.s[v] = 1.0;
        else if (gi[v] < kInf && go[v] < kInf) field.s[v] = gi[v] + go[v] > 0.0 ? gi[v] / (gi[v] + go[v]) : 0.5;
    }
    resolve_components(rings, inner, outer, field);
    warn_if_thin(positions, rings, gi, band, field);
    return field;
}

}  // namespace vfsd
