#pragma once
// The four per-step passes of sec. 5 (and the midpoint predictor, the
// deformation pass over half a step) on the GPU,
// one fragment shader each, with the names of their CPU counterparts in
// engine/deform/passes.h. All state lives in textures laid out by TextureLayout:
//
//   vertex texture    RGBA32F  xyz = position, w = s   (three: the committed
//                     positions, a staged step's, the next pass's target)
//   midpoint texture  RGBA32F  xyz = predicted midpoint, w = s
//   normal texture    RGBA32F  xyz = normal
//   gradient texture  RGBA32F  xyz = ∇r                (two, ping-pong while smoothing)
//   ring texture      RG32I    first ring entry, ring length
//   neighbour texture R32I     (neighbour << 1) | wedge flag, any valence
//
// Beyond sec. 5, the passes of the CPU's default scheme (deform/cpu_steps.h):
// the gauge samples' gather, the volume keeper's sums, velocity and Newton step, and the
// fold test; sums over the mesh are added up on the GPU (sum.frag) into one texel.
//
// Positions are float32 on the GPU (the CPU reference is double); docs/gpu.md
// gives the measured differences. Only the read_* functions read back, and each
// read-back is counted (gl_objects.h: readback_count()).

#include <cstddef>
#include <vector>

#include "deform/fold_repair.h"
#include "deform/passes.h"
#include "gpu/gl_objects.h"
#include "gpu/texture_layout.h"
#include "mesh/vertex_rings.h"

namespace vfsd::gpu {

// Which vertex texture a pass works on: the positions at t or the predicted midpoints.
enum class At { positions, midpoints };

class GpuPasses {
public:
    // Uploads the mesh (positions, s, rings) into textures. Needs a current GL
    // context; throws GpuUnavailable when it lacks float render targets or the
    // texture size, GpuError when a shader fails, InputError when sizes disagree.
    GpuPasses(const std::vector<Vec3>& positions, const std::vector<double>& s, const VertexRings& rings);

    // Normal pass: normal texture from the vertex (or midpoint) texture.
    void estimate_normals(At at);
    // Gradient pass, eq. (6): gradient texture from the vertex texture and normals.
    void estimate_gradients(At at);
    // Smoothing pass, `steps` times (ping-pong); s is taken from the vertex texture.
    void smooth_gradients(int steps, double weight, bool tangent);
    // Midpoint predictor: the deformation pass over half the step (`half`) by the
    // midpoint rule, from the positions with the current gradients into the
    // midpoint texture.
    void predict_midpoints(const StepMotion& half);
    // Deformation pass: one RK4 step of the positions; the new positions become current.
    void deformation_step(const StepMotion& motion);
    // The same, with the volume keeper after it where asked, kept aside: the
    // passes that follow (the fold test, the keeper) see the step's positions,
    // but read_positions() and vertex_texture() the last committed ones until
    // commit_step(); discard_step() drops it (a step begun ahead, in pieces, that
    // no step takes: deform/deformation.h, StepBackend::prepare_step).
    void stage_step(const StepMotion& motion, bool keep_volume);
    void commit_step();
    void discard_step();

    // Beyond the paper. The stream gauge's samples (field/stream_gauge.h): the
    // vertices are set once; each read is one read-back of two texels per sample,
    // its position (or midpoint) and its ∇r, for the fit on the CPU.
    void set_gauge_samples(const std::vector<std::uint32_t>& vertices);
    void read_gauge_samples(At at, std::vector<Vec3>& positions, std::vector<Vec3>& gradients) const;
    // The same in two halves, so that the GPU can run the gather before the read
    // waits for it (a fence between: gl_objects.h).
    void gather_gauge_samples(At at) const;
    void read_gathered_samples(std::vector<Vec3>& positions, std::vector<Vec3>& gradients) const;
    // The volume keeper (deform/volume_keeper.h) on a closed mesh: measure_rest_volume
    // takes the sums of the current positions about `centre` as the rest's, once;
    // keep_volume then moves the blend vertices by one Newton step on the volume,
    // along the area vectors of the last normal pass. No read-back.
    void measure_rest_volume(const Vec3& centre);
    void keep_volume();
    // The keeper's velocity for the deformation passes that follow: the keeper
    // rate pass at the positions or midpoints with the last normals and ∇r, the
    // field of `sample` (VolumeKeeper::rate and lambda). None until the
    // first, or without measure_rest_volume.
    void keeper_rate(At at, const MotionSample& sample);
    // The fold test (FoldRepair::folded): the checks are uploaded once, their
    // triangles' corners mapped to this mesh's vertices by `to_vertex`; each count
    // is one read-back of a single texel.
    void set_fold_checks(const FoldChecks& checks, const std::vector<std::uint32_t>& to_vertex);
    std::size_t count_folds() const;
    // The same in two halves: the test and its sum, then the read-back of the count.
    void test_folds() const;
    std::size_t read_fold_count() const;

    // Replace GPU state (tests, restarts); uploads are not read-backs.
    void set_positions(const std::vector<Vec3>& positions);
    void set_gradients(const std::vector<Vec3>& gradients);
    // A new s for the next set_positions() (the vertex texture's w).
    void set_region(const std::vector<double>& s);
    // Read GPU state back (each call is one counted read-back).
    std::vector<Vec3> read_positions() const;
    std::vector<Vec3> read_staged_positions() const;  // a staged step's, before commit_step()
    std::vector<Vec3> read_midpoints() const;
    std::vector<Vec3> read_normals() const;
    std::vector<Vec3> read_gradients() const;

    // The current vertex texture (xyz + s), for drawing without read-back. Its
    // positions are relative to vertex_origin(), the centre of the mesh's bounding
    // box at upload: float32 keeps its precision for a mesh far from the origin.
    const Texture& vertex_texture() const { return vertex_[committed_].texture; }
    const Vec3& vertex_origin() const { return origin_; }
    std::size_t vertex_count() const { return count_; }
    const TextureLayout& layout() const { return layout_; }

private:
    struct Target {
        Texture texture;
        Framebuffer framebuffer;
    };
    Target make_target() const;
    Target make_target(int width, int height) const;
    std::vector<Target> sum_levels(int width, int height) const;
    void sum(const Texture& source, const std::vector<Target>& levels) const;
    void sum_volume(const std::vector<Target>& levels) const;
    const Texture& source(At at) const;
    void bind_mesh(const Program& program) const;
    void draw(const Target& target) const;
    void draw_deformation(const StepMotion& motion, const Target& target, bool midpoint_rule) const;
    int spare() const;
    void keep_volume_staged();
    std::vector<float> packed(const std::vector<Vec3>& xyz, bool with_s, const Vec3& origin) const;
    std::vector<Vec3> read(const Target& target, const Vec3& origin) const;

    std::size_t count_ = 0;
    int max_texture_size_ = 1;
    TextureLayout layout_;
    Vec3 origin_{0.0};
    std::vector<float> s_;  // s as uploaded (float32, see upload rules in the .cpp)
    Texture rings_, neighbours_;
    Target vertex_[3], midpoint_, normal_, gradient_[2];
    // Three vertex textures: the committed positions, the working ones (a staged
    // step's) and one the next pass writes into.
    int current_ = 0, committed_ = 0, current_gradient_ = 0;
    Program normal_program_, gradient_program_, smooth_program_, deform_program_;
    VertexArray empty_vao_;
    // Beyond the paper, each made by its set_ or measure_ call.
    Program sum_program_;
    std::size_t gauge_sample_count_ = 0;
    Texture gauge_sample_vertices_;
    Target gauge_samples_;
    Program gauge_samples_program_;
    Vec3 volume_centre_{0.0};  // relative to origin_
    Target volume_terms_;
    std::vector<Target> volume_sums_, rest_volume_sums_, keeper_sums_;
    bool keeper_rated_ = false;
    Program volume_program_, keep_volume_program_, keeper_rate_program_;
    std::size_t fold_check_count_ = 0;
    Texture fold_triangles_, fold_checks_, fold_neighbours_;
    Target fold_flags_;
    std::vector<Target> fold_sums_;
    Program fold_program_;
};

}  // namespace vfsd::gpu
