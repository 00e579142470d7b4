// Wavefront OBJ: `v x y z [w]` and `f` with v, v/vt, v//vn or v/vt/vn corners
// (1-based, negative = relative to the last vertex). Every other statement
// (vt, vn, o, g, s, usemtl, mtllib, l, ...) is ignored.

#include <string>

#include "io/format_io.h"

namespace vfsd::io {
namespace {

// The vertex index of one `f` corner such as "7", "7/2", "7//3" or "-1/-1/-1".
std::uint32_t obj_corner(const TextCursor& cursor, std::string_view token, std::size_t vertex_count) {
    const std::string_view index_text = token.substr(0, token.find('/'));
    const long long index = cursor.to_integer(index_text);
    const long long n = static_cast<long long>(vertex_count);
    if (index == 0) cursor.fail("face index 0 is invalid (OBJ indices start at 1)");
    const long long zero_based = index > 0 ? index - 1 : n + index;
    if (zero_based < 0 || zero_based >= n) {
        cursor.fail("face index " + std::string(index_text) + " is out of range (" + std::to_string(n) + " vertices so far)");
    }
    return static_cast<std::uint32_t>(zero_based);
}

}  // namespace

TriangleMesh read_obj(const std::string& path, const std::string& text) {
    TextCursor cursor(path, text);
    TriangleMesh mesh;
    std::vector<std::uint32_t> corners;
    std::string_view line;
    while (cursor.next_line(line)) {
        const std::vector<std::string_view> tokens = split_tokens(line);
        if (tokens.empty()) continue;
        if (tokens[0] == "v") {
            if (tokens.size() < 4) cursor.fail("vertex needs three coordinates");
            mesh.positions.emplace_back(cursor.to_double(tokens[1]), cursor.to_double(tokens[2]), cursor.to_double(tokens[3]));
        } else if (tokens[0] == "f") {
            if (tokens.size() < 4) cursor.fail("face needs at least three vertices");
            corners.clear();
            for (std::size_t k = 1; k < tokens.size(); ++k) corners.push_back(obj_corner(cursor, tokens[k], mesh.positions.size()));
            append_fan(mesh.triangles, corners);
        }
    }
    require_triangles(cursor, mesh);
    return mesh;
}

std::string write_obj(const TriangleMesh& mesh) {
    std::string out = "# written by vfsd\n";
    for (const Vec3& p : mesh.positions) out += "v " + format_position(p) + "\n";
    for (const Triangle& t : mesh.triangles) out += "f " + format_triangle(t, 1) + "\n";
    return out;
}

}  // namespace vfsd::io
