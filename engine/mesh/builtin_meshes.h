#pragma once
// The paper's synthetic models as closed, manifold, outward-oriented meshes.
// `resolution` scales the tessellation; 0 selects the default, whose vertex count
// lands near the paper's (sec. 7.1): box 2,462, bar 9,730, cylinder 21,302.

#include <string>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace vfsd {

TriangleMesh make_builtin_mesh(const std::string& name, int resolution = 0);

// "box", "bar", "cylinder", "sphere".
std::vector<std::string> builtin_mesh_names();

}  // namespace vfsd
