// Object File Format (OFF, also COFF/NOFF/STOFF headers): a header line, the
// counts "vertices faces edges", the vertex lines, then faces "n i0 .. i(n-1)".
// '#' starts a comment; extra values (colours, normals) are ignored.

#include <string>

#include "io/format_io.h"

namespace vfsd::io {
namespace {

// The tokens of the next line that holds data (skipping blanks and comments).
bool next_data_line(TextCursor& cursor, std::vector<std::string_view>& tokens) {
    std::string_view line;
    while (cursor.next_line(line)) {
        tokens = split_tokens(line.substr(0, line.find('#')));
        if (!tokens.empty()) return true;
    }
    return false;
}

bool ends_with_off(std::string_view token) { return token.size() >= 3 && token.substr(token.size() - 3) == "OFF"; }

// Reads the header and the counts line; returns {vertex count, face count}.
std::pair<long long, long long> read_off_header(TextCursor& cursor) {
    std::vector<std::string_view> tokens;
    if (!next_data_line(cursor, tokens)) cursor.fail("empty file");
    if (!ends_with_off(tokens[0])) cursor.fail("not an OFF file: expected 'OFF', got " + quoted(tokens[0]));
    if (tokens.size() > 1 && tokens[1] == "BINARY") cursor.fail("binary OFF is not supported");
    tokens.erase(tokens.begin());
    if (tokens.empty() && !next_data_line(cursor, tokens)) cursor.fail("missing the vertex and face counts");
    if (tokens.size() < 2) cursor.fail("expected 'vertices faces edges' counts");
    const long long vertices = cursor.to_integer(tokens[0]);
    const long long faces = cursor.to_integer(tokens[1]);
    if (vertices < 0 || faces < 0) cursor.fail("negative count");
    return {vertices, faces};
}

void read_off_face(TextCursor& cursor, const std::vector<std::string_view>& tokens, TriangleMesh& mesh,
                   std::vector<std::uint32_t>& corners) {
    const long long n = cursor.to_integer(tokens[0]);
    if (n < 3) cursor.fail("face needs at least three vertices, has " + quoted(tokens[0]));
    if (static_cast<std::size_t>(n) >= tokens.size()) {
        cursor.fail("face declares " + std::to_string(n) + " vertices but lists " + std::to_string(tokens.size() - 1));
    }
    corners.clear();
    for (long long k = 1; k <= n; ++k) {
        const long long index = cursor.to_integer(tokens[k]);
        if (index < 0 || index >= static_cast<long long>(mesh.positions.size())) {
            cursor.fail("vertex index " + std::to_string(index) + " is out of range (" + std::to_string(mesh.positions.size()) +
                        " vertices)");
        }
        corners.push_back(static_cast<std::uint32_t>(index));
    }
    append_fan(mesh.triangles, corners);
}

}  // namespace

TriangleMesh read_off(const std::string& path, const std::string& text) {
    TextCursor cursor(path, text);
    const auto [vertex_count, face_count] = read_off_header(cursor);
    TriangleMesh mesh;
    std::vector<std::string_view> tokens;
    // Declared counts are trusted only as far as lines are actually there.
    for (long long v = 0; v < vertex_count; ++v) {
        if (!next_data_line(cursor, tokens)) cursor.fail("file ends after " + std::to_string(v) + " of " + std::to_string(vertex_count) + " vertices");
        if (tokens.size() < 3) cursor.fail("vertex needs three coordinates");
        mesh.positions.emplace_back(cursor.to_double(tokens[0]), cursor.to_double(tokens[1]), cursor.to_double(tokens[2]));
    }
    std::vector<std::uint32_t> corners;
    for (long long f = 0; f < face_count; ++f) {
        if (!next_data_line(cursor, tokens)) cursor.fail("file ends after " + std::to_string(f) + " of " + std::to_string(face_count) + " faces");
        read_off_face(cursor, tokens, mesh, corners);
    }
    require_triangles(cursor, mesh);
    return mesh;
}

std::string write_off(const TriangleMesh& mesh) {
    std::string out = "OFF\n" + std::to_string(mesh.vertex_count()) + " " + std::to_string(mesh.triangle_count()) + " 0\n";
    for (const Vec3& p : mesh.positions) out += format_position(p) + "\n";
    for (const Triangle& t : mesh.triangles) out += "3 " + format_triangle(t, 0) + "\n";
    return out;
}

}  // namespace vfsd::io
