#pragma once
// Keeps the enclosed volume of a closed mesh (sec. 7.2: the signed tetrahedra of
// the triangles with the origin) at its value before the deformation.
//
// The field is divergence-free, so its flow keeps every volume; the discrete
// scheme does not quite (∇r is estimated per vertex, the surface is sampled at
// its vertices), and the error grows with the deformation: on the scene battery
// the median drift was 0.4 %, the worst 2 % (docs/method.md). That drift is the
// field's, not the step's: it is the same at 100 steps and at 8000. So the keeper
// adds a velocity to the field, u = λ w ∂V/∂x on the blend vertices, w = (1 − b)
// b′(s): a smooth bump over the blend region that vanishes where it meets the
// inner region (which stays rigid) and the outer region (which stays put). It is
// held over the step, as ∇r is, where the step takes ∇r (its middle), with ∂V/∂x
// the one the step's normal pass found there (a sixth of the vertex's ring area
// vector, mesh/geometry.h) and λ such that dV/dt = 0 there (lambda(), from
// rate()). After the step, one Newton step on the volume constraint along the
// same w ∂V/∂x undoes what is left, the step's own error (restore()). Undoing
// the whole drift after each step instead, a splitting, made the scheme first
// order in time (docs/method.md, "The volume keeper inside the step").

#include <vector>

#include "curve/inner_motion.h"
#include "mesh/vertex_rings.h"

namespace vfsd {

class VolumeKeeper {
public:
    // Newton steps after a step the fold repair moved vertices in, each with the
    // area vectors where the last one left them: a repair can move many vertices
    // by up to an edge, and one step's second-order error then stays (0.48 % on
    // a battery scene whose last step was repaired; docs/method.md).
    static constexpr int kStepsAfterRepair = 3;
    // A drift within this share of the volume is settled: the Newton steps after
    // a repair stop there (restore_after_repair). Past it a step moves by little
    // more than the volume sum's rounding (on the raised claw the second step's
    // drift was 1e-15 to 6e-13 of the volume after a repair, the third's about 1e-16).
    static constexpr double kSettledDrift = 1e-12;

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
    // The same with area_norm(area_vectors) known (the step took it for lambda()
    // where it estimated its normals): one sum over the blend region less a step.
    double restore(std::vector<Vec3>& positions, const std::vector<Vec3>& area_vectors, double area_norm) const;
    // After a step the fold repair moved vertices in (`positions` where it left
    // them): Newton steps on the volume, each with the blend vertices' area
    // vectors where the last left them (into `area_vectors`, their area_norm into
    // `area_norm`), until the drift is settled (kSettledDrift), at most
    // kStepsAfterRepair. Returns the steps taken; where it takes none,
    // `area_vectors` and `area_norm` are left as they were.
    int restore_after_repair(std::vector<Vec3>& positions, const VertexRings& rings, std::vector<Vec3>& area_vectors,
                             double& area_norm) const;
    // Σ w |∂V/∂x|² over the blend vertices, area_vectors as for restore(): what
    // lambda() and restore() divide by.
    double area_norm(const std::vector<Vec3>& area_vectors) const;

    // dV/dt of the mesh at `positions` moving with the field of `sample`: rigid
    // on the inner region, v on the blend region, whose share of 6 dV/dt is
    // `blend_flux` (deform/passes.h), 0 on the outer region.
    double rate(const std::vector<Vec3>& positions, double blend_flux, const MotionSample& sample) const;
    // λ of the keeper's velocity u = λ w ∂V/∂x on the blend vertices
    // (KeeperVelocity, deform/passes.h), whose share of dV/dt cancels `rate`: a
    // step that adds it to the field keeps the volume to its own order, so that
    // restore() after it undoes only the step's error. area_vectors as for
    // restore(), where `rate` was taken; 0 where a sum is not finite.
    double lambda(double rate, const std::vector<Vec3>& area_vectors) const {
        return lambda(rate, area_norm(area_vectors));
    }
    double lambda(double rate, double area_norm) const;

private:
    double moving_volume(const std::vector<Vec3>& positions) const;
    // The Newton step of restore() for a known drift (volume − rest volume).
    void move_by(std::vector<Vec3>& positions, const std::vector<Vec3>& area_vectors, double area_norm,
                 double drift) const;
    // std::invalid_argument unless there is one area vector per blend vertex.
    void require_one_per_blend_vertex(const std::vector<Vec3>& area_vectors, const char* caller) const;
    void find_inner_border(const std::vector<double>& s, const VertexRings& rings);

    bool active_ = false;
    std::vector<std::uint32_t> blend_;
    std::vector<double> weight_;   // w per blend vertex
    std::vector<Triangle> moving_;  // the triangles with a corner that moves (s < 1)
    // For rate(): (v, a, b) per inner corner v of a triangle v → a → b with a
    // corner outside the inner region, and the inner region's border.
    std::vector<Triangle> inner_terms_;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> inner_border_;
    Vec3 centre_{0.0};             // volumes are summed about it: exact for a closed surface, and no cancellation far from the origin
    double rest_volume_ = 0.0, fixed_volume_ = 0.0;
};

}  // namespace vfsd
