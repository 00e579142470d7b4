// STL, binary (80-byte header, uint32 count, 50 bytes per triangle) and ascii
// ("solid ... facet ... outer loop, vertex x y z (three times) ... endsolid").
// STL stores three corners per triangle; mesh_file.cpp welds them. Normals are
// ignored (the winding defines the orientation).

#include <string>

#include "io/format_io.h"

namespace vfsd::io {
namespace {

constexpr std::size_t kHeaderBytes = 84;
constexpr std::size_t kTriangleBytes = 50;

// A binary file's size is exactly determined by its count; ascii files begin with "solid".
bool is_binary_stl(const std::string& bytes) {
    if (bytes.size() < kHeaderBytes) return false;
    std::uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    return kHeaderBytes + kTriangleBytes * static_cast<std::uint64_t>(count) == bytes.size();
}

TriangleMesh read_binary_stl(const std::string& path, const std::string& bytes) {
    ByteCursor cursor(path, bytes, 80);
    const std::uint32_t count = cursor.read<std::uint32_t>();
    TriangleMesh mesh;
    mesh.positions.reserve(3 * static_cast<std::size_t>(count));  // the size check in is_binary_stl bounds count
    mesh.triangles.reserve(count);
    for (std::uint32_t t = 0; t < count; ++t) {
        cursor.skip(12);  // the facet normal
        for (int k = 0; k < 3; ++k) {
            const float x = cursor.read<float>(), y = cursor.read<float>(), z = cursor.read<float>();
            mesh.positions.emplace_back(x, y, z);
        }
        cursor.skip(2);  // attribute byte count
        mesh.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    }
    check_mesh(path, mesh);
    return mesh;
}

// One statement of an ascii STL; `corners` counts the vertices of the open loop (-1: no loop).
void read_ascii_statement(TextCursor& cursor, const std::vector<std::string_view>& tokens, TriangleMesh& mesh, int& corners) {
    const std::string_view key = tokens[0];
    if (key == "vertex") {
        if (corners < 0) cursor.fail("vertex outside an 'outer loop'");
        if (corners == 3) cursor.fail("loop has more than three vertices");
        if (tokens.size() != 4) cursor.fail("vertex needs three coordinates");
        mesh.positions.emplace_back(cursor.to_double(tokens[1]), cursor.to_double(tokens[2]), cursor.to_double(tokens[3]));
        ++corners;
    } else if (key == "outer") {
        if (corners >= 0) cursor.fail("'outer loop' inside another loop");
        corners = 0;
    } else if (key == "endloop") {
        if (corners != 3) cursor.fail("loop has " + std::to_string(std::max(corners, 0)) + " vertices, expected 3");
        const auto n = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.triangles.push_back({n - 3, n - 2, n - 1});
        corners = -1;
    } else if (key != "facet" && key != "endfacet" && key != "endsolid" && key != "solid") {
        cursor.fail("unexpected " + quoted(key) + " in ascii STL");
    }
}

TriangleMesh read_ascii_stl(const std::string& path, const std::string& text) {
    TextCursor cursor(path, text);
    TriangleMesh mesh;
    int corners = -1;
    std::string_view line;
    while (cursor.next_line(line)) {
        const std::vector<std::string_view> tokens = split_tokens(line);
        if (!tokens.empty()) read_ascii_statement(cursor, tokens, mesh, corners);
    }
    if (corners >= 0) cursor.fail("file ends inside a loop");
    require_triangles(cursor, mesh);
    return mesh;
}

}  // namespace

TriangleMesh read_stl(const std::string& path, const std::string& bytes) {
    if (is_binary_stl(bytes)) return read_binary_stl(path, bytes);
    if (bytes.compare(0, 5, "solid") == 0) return read_ascii_stl(path, bytes);
    if (bytes.size() < kHeaderBytes) ByteCursor(path, bytes).fail("too short for a binary STL and not ascii STL");
    ByteCursor(path, bytes).fail("size does not match the binary STL's triangle count and it is not ascii STL");
}

}  // namespace vfsd::io
