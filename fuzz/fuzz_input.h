#pragma once
// What one fuzz input does, shared by the libFuzzer targets (fuzz_target.cpp) and
// the regression test (tests/test_fuzz_regressions.cpp), so a saved input replays
// exactly as it was found.
//
//   obj off ply stl  read_mesh_bytes (PLY and STL choose ascii or binary themselves)
//   gltf             GLB when the bytes start with the magic "glTF", JSON glTF otherwise
//   scene            parse_scene_json + parse_scene; when the scene parses, prepare it
//                    on a small builtin box (the scene's own mesh is never read) and
//                    integrate at most 4 steps with little smoothing, so a run stays fast
//
// run_fuzz_input returns normally or throws vfsd::Error; anything else is a bug.

#include <algorithm>
#include <string>
#include <vector>

#include "base/error.h"
#include "io/mesh_file.h"
#include "mesh/builtin_meshes.h"
#include "scene/prepared_scene.h"

namespace vfsd::fuzz {

inline const std::vector<std::string>& fuzz_targets() {
    static const std::vector<std::string> names = {"obj", "off", "ply", "stl", "gltf", "scene"};
    return names;
}

inline void run_scene_input(const std::string& bytes) {
    static const MeshFile box = weld_mesh(make_builtin_mesh("box", 2), "builtin");  // 26 vertices
    Scene scene = parse_scene(parse_scene_json(bytes, "fuzz.json"), "", "fuzz.json");
    scene.options.steps = std::min(scene.options.steps, 4);
    scene.options.smoothing_steps = std::min(scene.options.smoothing_steps, 3);
    scene.region.geodesic.smoothing_iterations = std::min(scene.region.geodesic.smoothing_iterations, 3);
    const PreparedScene prepared = prepare_scene(scene, box);
    Deformation deformation = prepared.start_deformation();
    deformation.advance(scene.target_time);
}

inline void run_mesh_input(std::string format, const std::string& bytes) {
    if (format == "gltf" && bytes.compare(0, 4, "glTF") == 0) format = "glb";
    const MeshFile file = read_mesh_bytes(bytes, format, "fuzz." + format);
    const std::size_t n = file.mesh.vertex_count();
    for (const Triangle& t : file.mesh.triangles)
        if (t[0] >= n || t[1] >= n || t[2] >= n) throw std::logic_error("welded mesh has an index out of range");
}

inline void run_fuzz_input(const std::string& target, const std::string& bytes) {
    if (target == "scene") run_scene_input(bytes);
    else run_mesh_input(target, bytes);
}

}  // namespace vfsd::fuzz
