#pragma once
// A scene file written with what it needs to be read again elsewhere: the editors'
// "Save scene", the page's "Export scene" and the autosave (editor/autosave.h).

#include <string>

#include "mesh/triangle_mesh.h"
#include "scene/scene.h"

namespace vfsd {

// How a scene refers to its input mesh file (not builtin:, not applied): by a path
// relative to the scene, or by a copy of the file beside the scene
// (NAME.input.EXT), so that the scene's folder holds all it needs (the autosave).
// A .gltf, whose buffers may be files beside it, is always referenced.
enum class InputMesh { referenced, copied };

// Writes `scene` to `path` (atomically; a failure throws IoError and leaves any
// existing file as it was). `baked`, when given, is a mesh that exists only in
// memory (an applied deformation): it is written beside the scene as
// NAME.mesh.ply (float64 positions) and named in it.
void write_scene_package(const std::string& path, Scene scene, InputMesh input = InputMesh::referenced,
                         const TriangleMesh* baked = nullptr);

}  // namespace vfsd
