#pragma once
// A scene made ready to integrate: the mesh read and welded, its 1-rings, the
// region field s computed (sec. 6), the motion built (sec. 4.2, 6.2), and the
// warnings a user should see before starting.

#include <optional>
#include <string>
#include <vector>

#include "io/mesh_file.h"
#include "region/harmonic_blend.h"
#include "scene/scene.h"

namespace vfsd {

struct PreparedScene {
    Scene scene;
    MeshFile file;  // file.mesh is the welded mesh the engine deforms
    VertexRings rings;
    Region region;  // s per vertex (for the sphere tool: its value at the start)
    InnerMotion motion;
    std::vector<std::string> warnings;

    Deformation start_deformation() const&;
    // The same, the positions, rings and region moved into it instead of copied.
    Deformation start_deformation() &&;
};

// Computes s for the mesh's current positions; call again with deformed positions
// to recompute the region on the deformed shape (sec. 3).
Region build_region(const RegionSpec& spec, const std::vector<Vec3>& positions, const VertexRings& rings,
                    std::vector<std::string>& warnings);

// build_region in parts, for an editor that spreads the work over frames: the
// constructor computes eq. (15) or (16) (and throws InputError for what
// build_region rejects), advance() sets up the harmonic blend's system in a
// part of its own and then solves it for about a budget at a time. The region
// is build_region's, bit for bit, however the parts fall (build_region is this,
// run to the end). `positions` and `rings` must stay as they are until it is built.
class RegionBuild {
public:
    RegionBuild(const RegionSpec& spec, const std::vector<Vec3>& positions, const VertexRings& rings);
    // Works for about `budget_ms` (infinity: to the end); true once the region is built.
    bool advance(double budget_ms);
    bool built() const { return !blend_wanted_; }
    // s so far. Which vertices are inner (s <= 0), blend and outer (s >= 1) is
    // final from the start: the blend changes only the blend vertices' values.
    const std::vector<double>& s() const { return blend_ ? blend_->s() : region_.s; }
    // The region and its warnings, once built().
    Region take(std::vector<std::string>& warnings);

private:
    const std::vector<Vec3>& positions_;
    const VertexRings& rings_;
    Region region_;
    std::vector<std::string> warnings_;
    bool blend_wanted_ = false;           // the harmonic profile, until solved
    std::optional<HarmonicBlend> blend_;  // its system, once set up
};

// Reads the scene's mesh (throws InputError / IoError) and prepares everything.
PreparedScene prepare_scene(const Scene& scene);
// Same, on a mesh already in memory (the editors' current mesh).
PreparedScene prepare_scene(const Scene& scene, MeshFile file);
// Same, with the mesh's rings and scene.region's region on it already built (an
// editor keeps both while the user edits): nothing is computed twice.
PreparedScene prepare_scene(const Scene& scene, MeshFile file, VertexRings rings, Region region);

}  // namespace vfsd
