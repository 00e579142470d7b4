#pragma once
// A battery of generated scenes: scenes nobody tuned, to hold the engine to the
// method's promises (no local folds, volume kept, the outer region in place, the
// inner region rigid) on any mesh, placement, size, region kind and motion.
// Scene k of seed N is the same on every machine (its own random numbers, no
// std:: distributions), so a failure is reproduced by its seed and index.

#include <cstdint>
#include <string>
#include <vector>

#include "io/mesh_file.h"
#include "mesh/vertex_rings.h"
#include "region/region_field.h"
#include "scene/scene.h"
#include "scene/scene_transform.h"

namespace vfsd {

struct BatteryScene {
    std::string name;         // "0007-armadillo-geodesic-curve2"
    std::string mesh_source;  // what the mesh was loaded from, before placement
    Scene scene;              // in placed coordinates; scene.mesh is mesh_source
    MeshFile mesh;            // placed
    Placement placement;
    std::string region_kind;  // geodesic | selectors | vertex-lists | painted-s
    std::string motion_kind;  // curveN (N segments) | handle
    double bend_degrees = 0.0;
    double move_over_inner = 0.0;  // curve length over the inner region's size
    double twist_degrees = 0.0;
    int blend_rings = 0;  // the fewest edges from an inner to an outer vertex (blend_ring_width)
};

// The blend region's narrowest width in rings (blend_ring_width, region/region_field.h)
// that every battery scene has at least.
constexpr int kBatteryBlendRings = 6;

// The meshes a battery draws from: each built-in at a coarse and a fine
// resolution, then every mesh file in `mesh_files` (e.g. CGAL's, assets/cgal).
std::vector<std::string> battery_mesh_sources(const std::vector<std::string>& mesh_files, bool fine_builtins = true);

// Why a mesh cannot host battery scenes ("" when it can): a battery scene needs
// a closed surface (so that its volume is defined), wound consistently in the
// file, one piece (so that every vertex has a geodesic distance) and at least
// kBatteryMinVertices vertices (so that an inner, a blend region six rings wide
// and an outer region fit on it). `any_surface`: a surface with borders, pinched
// vertices, non-manifold edges, triangles wound against their neighbours in the
// file or several pieces will do too (its volume may then be undefined; a
// geodesic region stays on its seed's piece), as users' meshes come. (Welding turns such triangles to agree,
// io/mesh_file.h; the default leaves their meshes out, so that its scenes stay those it has always made.)
constexpr std::size_t kBatteryMinVertices = 500;
std::string battery_mesh_unusable(const MeshFile& file, bool any_surface = false);

// Scene `index` of battery `seed` over `mesh_sources` (index picks the mesh in
// turn). At amplitude 1 bends reach 180°, twists ±180°, handles turn up to 90°
// and the curve is up to the inner region's size long; a smaller amplitude
// scales all four down (the same scene otherwise). Throws InputError when a mesh
// cannot be loaded.
BatteryScene generate_battery_scene(std::uint64_t seed, int index, const std::vector<std::string>& mesh_sources,
                                    double amplitude = 1.0);

}  // namespace vfsd
