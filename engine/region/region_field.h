#pragma once
// The region field s of sec. 3: one value in [0, 1] per vertex,
//   s = 0 -> full deformation (inner region), 0 < s < 1 -> blended, s = 1 -> no deformation.
// Two constructions from sec. 6:
//   - the geodesic level field (sec. 6.1, eq. 15) from one seed vertex and two thresholds;
//   - painted regions (sec. 6.2, eq. 16) from inner and outer vertex masks.
// Both take positions explicitly: calling again with deformed positions is the
// recompute that sec. 3 allows "on the user's request"; otherwise s stays as assigned.

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "mesh/vertex_rings.h"
#include "region/geodesic.h"

namespace vfsd {

struct RegionField {
    std::vector<double> s;              // one value in [0, 1] per vertex
    std::vector<std::string> warnings;  // conditions the caller should show the user
};

// Eq. (15), in the orientation sec. 3 and fig. 7 require (the printed equation has
// 0 and 1 swapped, which would hold the clicked vertex still; see docs/regions.md):
//   s = 0 for g <= g_min, s = 1 for g >= g_max, s = (g - g_min) / (g_max - g_min) between.
// Vertices no distance reaches (g = +infinity) get s = 1.
// Throws InputError unless 0 <= g_min < g_max and both are finite.
std::vector<double> level_field_from_distance(const std::vector<double>& g, double g_min, double g_max);

// Sec. 6.1: the approximate geodesic distance g from `seed`, mapped by eq. (15).
// Throws InputError for an out-of-range seed or invalid thresholds.
std::vector<double> geodesic_level_field(const std::vector<Vec3>& positions, const VertexRings& rings,
                                         std::uint32_t seed, double g_min, double g_max,
                                         const GeodesicOptions& options = {});

// Sec. 6.2, eq. (16): with g_i, g_o the approximate geodesic distances to the inner and
// the outer region (grown from their borders), s = g_i / (g_i + g_o); s is exactly 0 on
// inner vertices and exactly 1 on outer vertices. Per connected component:
//   - inner and outer both present: eq. (16);
//   - only outer (or beyond max_distance of the inner region): s = 1 (no deformation);
//   - only inner: s = 0, the whole component follows the inner deformation (a warning);
//   - neither: s = 1 (not moved, a warning).
// An empty inner region gives s = 1 everywhere and a warning (nothing moves).
// Throws InputError when a mask's size differs from the vertex count or when a vertex
// is marked both inner and outer.
//
// `band` > 0 opens a transition band where the regions meet: outer vertices nearer
// to the inner region than `band` (geodesic distance) join the blend region, so
// that painted regions that touch still blend over that width instead of tearing.
// With no outer region painted, every vertex at least `band` from the inner region
// is outer: an inner region painted alone blends over the band.
// A blend region thinner than kThinBlendRings somewhere gets a warning that says
// where and which band would widen it.
constexpr int kThinBlendRings = 3;
RegionField painted_region_field(const std::vector<Vec3>& positions, const VertexRings& rings,
                                 const std::vector<std::uint8_t>& inner, const std::vector<std::uint8_t>& outer,
                                 const GeodesicOptions& options = {}, double band = 0.0);

// The blend region's narrowest width in rings: the fewest edges on a path from a
// vertex with s = 0 to one with s = 1 (−1 when no such path exists).
int blend_ring_width(const std::vector<double>& s, const VertexRings& rings);

}  // namespace vfsd
