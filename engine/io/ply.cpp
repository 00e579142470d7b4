// Stanford PLY, ascii and binary (little- and big-endian). The "vertex" element
// gives x, y, z and, when present, the scalar "quality" or "s"; the "face" element
// gives the list "vertex_indices" (or "vertex_index"). Other elements and
// properties are read and skipped. Written as binary little-endian.

#include <cmath>
#include <optional>
#include <string>

#include "base/error.h"
#include "io/format_io.h"

namespace vfsd::io {
namespace {

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class PlyEncoding { Ascii, BinaryLittleEndian, BinaryBigEndian };

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::Float32;
    bool is_list = false;
    PlyType count_type = PlyType::UInt8;
};

struct PlyElement {
    std::string name;
    long long count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    PlyEncoding encoding = PlyEncoding::Ascii;
    std::vector<PlyElement> elements;
};

std::optional<PlyType> ply_type(std::string_view name) {
    static const std::pair<const char*, PlyType> names[] = {
        {"char", PlyType::Int8},     {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},    {"uint8", PlyType::UInt8},
        {"short", PlyType::Int16},   {"int16", PlyType::Int16},     {"ushort", PlyType::UInt16},  {"uint16", PlyType::UInt16},
        {"int", PlyType::Int32},     {"int32", PlyType::Int32},     {"uint", PlyType::UInt32},    {"uint32", PlyType::UInt32},
        {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64}, {"float64", PlyType::Float64}};
    for (const auto& [n, t] : names) {
        if (name == n) return t;
    }
    return std::nullopt;
}

std::size_t ply_size(PlyType t) {
    switch (t) {
        case PlyType::Int8: case PlyType::UInt8: return 1;
        case PlyType::Int16: case PlyType::UInt16: return 2;
        case PlyType::Int32: case PlyType::UInt32: case PlyType::Float32: return 4;
        case PlyType::Float64: return 8;
    }
    return 0;
}

PlyType parse_type(const TextCursor& cursor, std::string_view name) {
    const std::optional<PlyType> t = ply_type(name);
    if (!t) cursor.fail("unknown property type " + quoted(name));
    return *t;
}

void parse_header_line(TextCursor& cursor, const std::vector<std::string_view>& tokens, PlyHeader& header) {
    const std::string_view key = tokens[0];
    if (key == "format") {
        if (tokens.size() < 2) cursor.fail("format line needs an encoding");
        if (tokens[1] == "ascii") header.encoding = PlyEncoding::Ascii;
        else if (tokens[1] == "binary_little_endian") header.encoding = PlyEncoding::BinaryLittleEndian;
        else if (tokens[1] == "binary_big_endian") header.encoding = PlyEncoding::BinaryBigEndian;
        else cursor.fail("unknown PLY format " + quoted(tokens[1]));
    } else if (key == "element") {
        if (tokens.size() != 3) cursor.fail("expected 'element NAME COUNT'");
        const long long count = cursor.to_integer(tokens[2]);
        if (count < 0) cursor.fail("negative element count");
        header.elements.push_back({std::string(tokens[1]), count, {}});
    } else if (key == "property") {
        if (header.elements.empty()) cursor.fail("property before any element");
        PlyProperty p;
        if (tokens.size() == 5 && tokens[1] == "list") {
            p = {std::string(tokens[4]), parse_type(cursor, tokens[3]), true, parse_type(cursor, tokens[2])};
        } else if (tokens.size() == 3) {
            p = {std::string(tokens[2]), parse_type(cursor, tokens[1]), false, PlyType::UInt8};
        } else {
            cursor.fail("expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
        }
        header.elements.back().properties.push_back(p);
    } else if (key != "comment" && key != "obj_info") {
        cursor.fail("unexpected header line " + quoted(key));
    }
}

PlyHeader parse_header(TextCursor& cursor) {
    std::string_view line;
    if (!cursor.next_line(line) || line != "ply") cursor.fail("not a PLY file: the first line must be 'ply'");
    PlyHeader header;
    bool has_format = false;
    while (cursor.next_line(line)) {
        const std::vector<std::string_view> tokens = split_tokens(line);
        if (tokens.empty()) continue;
        if (tokens[0] == "end_header") {
            if (!has_format) cursor.fail("header has no format line");
            return header;
        }
        has_format = has_format || tokens[0] == "format";
        parse_header_line(cursor, tokens, header);
    }
    cursor.fail("file ends inside the header (no end_header)");
}

// The next value of the body, from ascii tokens or binary bytes.
class PlyBody {
public:
    PlyBody(const std::string& path, const std::string& bytes, TextCursor& text, PlyEncoding encoding)
        : text_(text), binary_(path, bytes, text.position()), encoding_(encoding) {}

    double value(PlyType type) {
        if (encoding_ == PlyEncoding::Ascii) return text_.to_double(next_token());
        const bool big = encoding_ == PlyEncoding::BinaryBigEndian;
        switch (type) {
            case PlyType::Int8: return binary_.read<std::int8_t>(big);
            case PlyType::UInt8: return binary_.read<std::uint8_t>(big);
            case PlyType::Int16: return binary_.read<std::int16_t>(big);
            case PlyType::UInt16: return binary_.read<std::uint16_t>(big);
            case PlyType::Int32: return binary_.read<std::int32_t>(big);
            case PlyType::UInt32: return binary_.read<std::uint32_t>(big);
            case PlyType::Float32: return binary_.read<float>(big);
            case PlyType::Float64: return binary_.read<double>(big);
        }
        return 0.0;
    }

    [[noreturn]] void fail(const std::string& what) const {
        if (encoding_ == PlyEncoding::Ascii) text_.fail(what);
        binary_.fail(what);
    }

    // A lower bound on the bytes `element` needs, to refuse declared counts the file cannot hold.
    void check_fits(const PlyElement& element) const {
        if (encoding_ == PlyEncoding::Ascii || element.count == 0) return;
        std::size_t bytes = 0;
        for (const PlyProperty& p : element.properties) bytes += p.is_list ? ply_size(p.count_type) : ply_size(p.type);
        if (bytes == 0) fail("element '" + element.name + "' has no properties");
        if (static_cast<unsigned long long>(element.count) > binary_.bytes_left() / bytes) {
            fail("declares " + std::to_string(element.count) + " " + element.name + " elements but only " +
                 std::to_string(binary_.bytes_left()) + " bytes of data follow");
        }
    }

private:
    std::string_view next_token() {
        while (index_ >= tokens_.size()) {
            std::string_view line;
            if (!text_.next_line(line)) text_.fail("unexpected end of file");
            tokens_ = split_tokens(line);
            index_ = 0;
        }
        return tokens_[index_++];
    }

    TextCursor& text_;
    ByteCursor binary_;
    PlyEncoding encoding_;
    std::vector<std::string_view> tokens_;
    std::size_t index_ = 0;
};

int find_property(const PlyElement& element, std::initializer_list<const char*> names) {
    for (std::size_t i = 0; i < element.properties.size(); ++i) {
        for (const char* n : names) {
            if (element.properties[i].name == n) return static_cast<int>(i);
        }
    }
    return -1;
}

// Reads one item of `element`: scalar properties into `values`, the list property `list_index` into `list`.
void read_item(PlyBody& body, const PlyElement& element, int list_index, std::vector<double>& values, std::vector<double>& list) {
    for (std::size_t i = 0; i < element.properties.size(); ++i) {
        const PlyProperty& p = element.properties[i];
        if (!p.is_list) {
            values[i] = body.value(p.type);
            continue;
        }
        const double n = body.value(p.count_type);
        if (n < 0 || n != std::floor(n)) body.fail("invalid list length in element '" + element.name + "'");
        if (static_cast<int>(i) == list_index) list.clear();
        for (double k = 0; k < n; ++k) {
            const double v = body.value(p.type);
            if (static_cast<int>(i) == list_index) list.push_back(v);
        }
    }
}

void read_vertices(PlyBody& body, const PlyElement& element, TriangleMesh& mesh) {
    const int x = find_property(element, {"x"}), y = find_property(element, {"y"}), z = find_property(element, {"z"});
    const int s = find_property(element, {"quality", "s"});
    if (x < 0 || y < 0 || z < 0) body.fail("vertex element lacks x, y or z");
    std::vector<double> values(element.properties.size()), list;
    for (long long v = 0; v < element.count; ++v) {
        read_item(body, element, -1, values, list);
        const Vec3 p(values[x], values[y], values[z]);
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            body.fail("vertex " + std::to_string(v) + " has a non-finite coordinate");
        }
        mesh.positions.push_back(p);
        if (s >= 0) mesh.scalar.push_back(values[s]);
    }
}

void read_faces(PlyBody& body, const PlyElement& element, long long vertex_count, TriangleMesh& mesh) {
    const int list_index = find_property(element, {"vertex_indices", "vertex_index"});
    if (list_index < 0 || !element.properties[list_index].is_list) body.fail("face element lacks the list vertex_indices");
    std::vector<double> values(element.properties.size()), list;
    std::vector<std::uint32_t> corners;
    for (long long f = 0; f < element.count; ++f) {
        read_item(body, element, list_index, values, list);
        if (list.size() < 3) body.fail("face " + std::to_string(f) + " has fewer than three vertices");
        corners.clear();
        for (double index : list) {
            if (index < 0 || index >= static_cast<double>(vertex_count) || index != std::floor(index)) {
                body.fail("face " + std::to_string(f) + " has vertex index " + format_number(index) + " out of range (" +
                          std::to_string(vertex_count) + " vertices)");
            }
            corners.push_back(static_cast<std::uint32_t>(index));
        }
        append_fan(mesh.triangles, corners);
    }
}

}  // namespace

TriangleMesh read_ply(const std::string& path, const std::string& bytes) {
    TextCursor text(path, bytes);
    const PlyHeader header = parse_header(text);
    const PlyElement* vertex = nullptr;
    for (const PlyElement& e : header.elements) vertex = e.name == "vertex" ? &e : vertex;
    if (!vertex) text.fail("header declares no vertex element");
    PlyBody body(path, bytes, text, header.encoding);
    TriangleMesh mesh;
    std::vector<double> values, list;
    for (const PlyElement& e : header.elements) {
        body.check_fits(e);
        if (e.name == "vertex") {
            read_vertices(body, e, mesh);
        } else if (e.name == "face") {
            read_faces(body, e, vertex->count, mesh);
        } else {
            if (e.count > 0 && e.properties.empty()) body.fail("element '" + e.name + "' has no properties");
            values.resize(e.properties.size());
            for (long long k = 0; k < e.count; ++k) read_item(body, e, -1, values, list);
        }
    }
    if (mesh.triangles.empty()) body.fail("contains no triangles");
    check_mesh(path, mesh);
    return mesh;
}

std::string write_ply(const TriangleMesh& mesh, const WriteOptions& options) {
    const bool scalar = options.write_scalar && mesh.has_scalar();
    const char* type = options.double_positions ? "double" : "float";
    std::string out = "ply\nformat binary_little_endian 1.0\ncomment written by vfsd\n";
    out += "element vertex " + std::to_string(mesh.vertex_count()) + "\n";
    for (const char* axis : {"x", "y", "z"}) out += std::string("property ") + type + " " + axis + "\n";
    if (scalar) out += std::string("property ") + type + " quality\n";
    out += "element face " + std::to_string(mesh.triangle_count()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    auto put = [&](double value) {
        if (options.double_positions) put_le(out, value);
        else put_le(out, static_cast<float>(value));
    };
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        for (int axis = 0; axis < 3; ++axis) put(mesh.positions[v][axis]);
        if (scalar) put(mesh.scalar[v]);
    }
    for (const Triangle& t : mesh.triangles) {
        put_le(out, std::uint8_t{3});
        for (int k = 0; k < 3; ++k) put_le(out, static_cast<std::int32_t>(t[k]));
    }
    return out;
}

}  // namespace vfsd::io
