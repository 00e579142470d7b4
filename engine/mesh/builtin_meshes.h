#pragma once
// The paper's synthetic models as closed, manifold, outward-oriented meshes.
// `resolution` scales the tessellation; 0 selects the default, whose vertex count
// lands near the paper's (sec. 7.1): box 2,462, bar 9,730, cylinder 21,302.
//
// All are centred at the origin; long axes run along z.
//   box       1 x 1 x 1.2 (twist, figs. 4, 5, 15). Six regular grids of square cells;
//             resolution = cells across x and y (z gets round(1.2 n)).
//             Default 19 x 19 x 23: 2,472 vertices, volume 1.2.
//   bar       1 x 1 x 9 (bending, fig. 13). Same construction; resolution = cells
//             across x and y, 9 n along z. Default 16 x 16 x 144: 9,730 vertices, volume 9.
//   cylinder  radius 0.5, length 5 (knot, fig. 14). Rings of nearly equilateral
//             triangles on the side, concentric rings on the caps; resolution =
//             vertices around. Default 103: 21,426 vertices, volume pi r^2 L - 0.05%.
//   sphere    radius 1, an icosphere; resolution = subdivision levels of the
//             icosahedron. Default 5: 10,242 vertices, volume 4/3 pi - 0.06%.
// Throws InputError for an unknown name or a resolution out of range.

#include <string>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace vfsd {

TriangleMesh make_builtin_mesh(const std::string& name, int resolution = 0);

// "box", "bar", "cylinder", "sphere".
std::vector<std::string> builtin_mesh_names();

}  // namespace vfsd
