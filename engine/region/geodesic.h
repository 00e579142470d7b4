#pragma once
// Approximate geodesic distance on a triangle mesh, as sec. 6.1 uses it: a
// shortest-path propagation from a set of sources followed by smoothing with a
// kernel of local support, "so that the resulting deformation is smooth".
//
// Methods (GeodesicMethod):
//   dijkstra             Dijkstra on the edge graph, as the paper does. Distances are
//                        upper bounds; paths zig-zag along edges, so the error grows
//                        with the distance (about 5-8% on a regular grid).
//   dijkstra_flip_links  Dijkstra on the edge graph plus one extra link across every
//                        pair of adjacent triangles (the edge a flip would create),
//                        with its length measured in the unfolded pair. Same
//                        algorithm, about twice the links, roughly a third of the error.
//   fast_marching        Fast marching on triangles (Kimmel & Sethian 1998) with the
//                        update that unfolds a virtual point source from the two known
//                        corners of a triangle (exact for a point source on a flat
//                        mesh); obtuse or non-causal cases fall back to edge updates.
//                        The most accurate of the three.
// docs/regions.md lists the measured errors and costs.
//
// Distances are computed from explicit positions, so calling again with deformed
// positions is the "recompute on the user's request" of sec. 3. Vertices that no
// source reaches (other connected components, or beyond max_distance) get +infinity.
// Every function throws InputError for inconsistent sizes or out-of-range indices.

#include <cstdint>
#include <limits>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "mesh/vertex_rings.h"
#include "region/surface_point.h"

namespace vfsd {

enum class GeodesicMethod { dijkstra, dijkstra_flip_links, fast_marching };

struct GeodesicOptions {
    // Fast marching by default: same cost as Dijkstra, an order of magnitude more
    // accurate (Dijkstra's distances run up to 41% long on a regular grid, which turns
    // a round brush or level set into a diamond). dijkstra reproduces the paper.
    GeodesicMethod method = GeodesicMethod::fast_marching;
    // Jacobi passes of the local smoothing kernel (each pass averages a vertex with its
    // 1-ring, so k passes have k-ring support). Source vertices are never smoothed.
    int smoothing_iterations = 2;
    // Propagation stops beyond this distance; farther vertices stay +infinity.
    double max_distance = std::numeric_limits<double>::infinity();
};

// The general form: `seeds[v]` is a known distance at v (finite, >= 0) or +infinity.
// Seeded vertices keep their value exactly; the others get the propagated distance.
std::vector<double> geodesic_distance_from_seeds(const std::vector<Vec3>& positions, const VertexRings& rings,
                                                 const std::vector<double>& seeds,
                                                 const GeodesicOptions& options = {});

// Distance to a set of source vertices (exactly 0 on each source).
std::vector<double> geodesic_distance(const std::vector<Vec3>& positions, const VertexRings& rings,
                                      const std::vector<std::uint32_t>& sources,
                                      const GeodesicOptions& options = {});

// Distance to a region given as a vertex mask (nonzero = in the region): exactly 0 on
// the region, grown outwards from its border vertices (sec. 6.2).
std::vector<double> geodesic_distance_to_region(const std::vector<Vec3>& positions, const VertexRings& rings,
                                                const std::vector<std::uint8_t>& region,
                                                const GeodesicOptions& options = {});

// Distance to a point inside a triangle: its corners are seeded with their Euclidean
// distance to the point (exact within the flat triangle).
std::vector<double> geodesic_distance_from_point(const std::vector<Vec3>& positions,
                                                 const std::vector<Triangle>& triangles,
                                                 const VertexRings& rings, const SurfacePoint& point,
                                                 const GeodesicOptions& options = {});

}  // namespace vfsd
