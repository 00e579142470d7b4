#pragma once
// Vertex selectors of the scene file contract:
//   SEL := {"sphere": [cx,cy,cz,radius]}        |p - c| <= radius
//        | {"box": [x0,y0,z0,x1,y1,z1]}         x0 <= x <= x1, y0 <= y <= y1, z0 <= z <= z1
//        | {"halfspace": [nx,ny,nz,d]}          n . p >= d  (n is not normalised)
//        | {"vertices": [i, ...]}               the listed vertex indices
// A JSON array of SEL selects the union. Selectors are evaluated on explicit positions,
// so evaluating again on deformed positions re-selects on the deformed shape.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "mesh/triangle_mesh.h"

namespace vfsd {

enum class SelectorKind { sphere, box, halfspace, vertices };

struct Selector {
    SelectorKind kind = SelectorKind::vertices;
    Vec3 a{0.0};        // sphere: centre; box: minimum corner; halfspace: normal n
    Vec3 b{0.0};        // box: maximum corner
    double value = 0.0;  // sphere: radius; halfspace: offset d
    std::vector<std::uint32_t> vertices;  // vertices: the indices
};

// Parses one SEL object or an array of them. Throws InputError naming the bad field,
// prefixed by `field` (e.g. "inner[1].sphere: expected 4 numbers [cx,cy,cz,radius]").
// Rejects a negative radius, a box with x1 < x0 (etc.), a zero halfspace normal,
// non-integer or negative vertex indices, unknown keys and objects with several keys.
std::vector<Selector> parse_selectors(const nlohmann::json& json, const std::string& field = "selector");

// The union of the selectors as a vertex mask (1 = selected). Throws InputError when a
// "vertices" index is out of range.
std::vector<std::uint8_t> select_vertices(const std::vector<Vec3>& positions, const std::vector<Selector>& selectors);

// The index of the vertex closest to `point` (lowest index on ties). Throws InputError
// for an empty vertex list or a non-finite point.
std::uint32_t nearest_vertex(const std::vector<Vec3>& positions, Vec3 point);

}  // namespace vfsd
