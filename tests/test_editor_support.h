#pragma once
// Helpers of the editor tests: run a session to its target, and what `vfsd deform`
// computes for a saved scene.

#include <string>
#include <vector>

#include "deform/deformation.h"
#include "editor/session.h"
#include "scene/prepared_scene.h"
#include "scene/scene.h"

namespace vfsd::test {

inline void run_to_target(editor::EditorSession& session) {
    while (session.moving()) session.update(5);
}

// The deformation `vfsd deform` computes for a scene file (CPU).
inline std::vector<Vec3> deform_scene_file(const std::string& path) {
    const Scene scene = load_scene(path);
    const PreparedScene prepared = prepare_scene(scene);
    Deformation deformation = prepared.start_deformation();
    deformation.advance(scene.target_time);
    return deformation.positions();
}

}  // namespace vfsd::test
