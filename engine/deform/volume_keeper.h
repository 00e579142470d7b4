#pragma once
// Keeps the enclosed volume of a closed mesh (sec. 7.2: the signed tetrahedra of
// the triangles with the origin) at its value before the deformation.
//
// The field is divergence-free, so its flow keeps every volume; the discrete
// scheme does not quite (∇r is estimated per vertex, the surface is sampled at
// its vertices), and the error grows with the deformation: on the scene battery
// the median drift was 0.4 %, the worst 2 % (docs/method.md). After every step
// one Newton step on the volume constraint moves the blend vertices along
// w ∂V/∂x, w = (1 − b) b′(s): a smooth bump over the blend region that vanishes
// where it meets the inner region (which stays rigid) and the outer region
// (which stays put). ∂V/∂x_v is the one the step's normal pass found at the
// step's midpoint (a sixth of the vertex's ring area vector, mesh/geometry.h):
// no ring pass of its own, and what half a step's change of the rings leaves
// of the drift is undone at the next step. The correction is reported, so the
// field's own drift stays visible.

#include <vector>

#include "mesh/vertex_rings.h"

namespace vfsd {

class VolumeKeeper {
public:
    // Newton steps after a step the fold repair moved vertices in, each with the
    // area vectors where the last one left them: a repair can move many vertices
    // by up to an edge, and one step's second-order error then stays (0.48 % on
    // a battery scene whose last step was repaired; docs/method.md).
    static constexpr int kStepsAfterRepair = 3;

    // `rest` and `s` in the rings' vertex order. Inactive (restore does nothing)
    // unless applies_to(rings): a surface with a border encloses no volume.
    VolumeKeeper(const std::vector<Vec3>& rest, const std::vector<double>& s, const VertexRings& rings,
                 const std::vector<std::uint32_t>& blend);
    VolumeKeeper() = default;

    // Whether a keeper of a mesh with these rings is active: every edge borders
    // two triangles. A vertex may join several fans (a pinch: two closed parts
    // touching there); the volume is then still their sum (deform/quality.h's
    // volume_defined says the same of the mesh).
    static bool applies_to(const VertexRings& rings);
    bool active() const { return active_; }
    double rest_volume() const { return rest_volume_; }
    // The volume of the mesh at `positions`.
    double volume(const std::vector<Vec3>& positions) const;
    // Moves the blend vertices of `positions` so that the volume is the rest
    // volume again (to first order in the drift and in the rings' change over
    // the step); returns the drift it undid. area_vectors[i] is blend vertex i's
    // ring area vector (6 ∂V/∂x) where the step estimated its normals, or where
    // the fold repair left it; std::invalid_argument if there is not one per
    // blend vertex (a caller's bug, not the user's).
    double restore(std::vector<Vec3>& positions, const std::vector<Vec3>& area_vectors) const;

private:
    double moving_volume(const std::vector<Vec3>& positions) const;

    bool active_ = false;
    std::vector<std::uint32_t> blend_;
    std::vector<double> weight_;   // w per blend vertex
    std::vector<Triangle> moving_; // the triangles with a corner that moves (s < 1)
    Vec3 centre_{0.0};             // volumes are summed about it: exact for a closed surface, and no cancellation far from the origin
    double rest_volume_ = 0.0, fixed_volume_ = 0.0;
};

}  // namespace vfsd
