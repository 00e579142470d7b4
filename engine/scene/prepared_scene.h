#pragma once
// A scene made ready to integrate: the mesh read and welded, its 1-rings, the
// region field s computed (sec. 6), the motion built (sec. 4.2, 6.2), and the
// warnings a user should see before starting.

#include <string>
#include <vector>

#include "io/mesh_file.h"
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

// Reads the scene's mesh (throws InputError / IoError) and prepares everything.
PreparedScene prepare_scene(const Scene& scene);
// Same, on a mesh already in memory (the editors' current mesh).
PreparedScene prepare_scene(const Scene& scene, MeshFile file);
// Same, with the mesh's rings and scene.region's region on it already built (an
// editor keeps both while the user edits): nothing is computed twice.
PreparedScene prepare_scene(const Scene& scene, MeshFile file, VertexRings rings, Region region);

}  // namespace vfsd
