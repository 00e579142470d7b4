#pragma once
// Internal to engine/io: the cursors the format readers share, and the per-format
// read and write functions that mesh_file.cpp dispatches to.
//
// Readers return the mesh as the file stores it (no welding); writers return the
// file's bytes, which mesh_file.cpp writes atomically.

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_file.h"
#include "mesh/triangle_mesh.h"

namespace vfsd::io {

// The whole file; throws IoError when it cannot be read.
std::string read_file_bytes(const std::string& path);

// Splits a text file into lines and a line into whitespace-separated tokens, and
// reports errors as "FILE:LINE: what".
class TextCursor {
public:
    TextCursor(const std::string& path, const std::string& text) : path_(path), text_(text) {}
    // The next line without its end-of-line characters; false at the end of the file.
    bool next_line(std::string_view& line);
    int line_number() const { return line_; }
    [[noreturn]] void fail(const std::string& what) const;
    // Parses a finite number / an integer that fills the whole token.
    double to_double(std::string_view token) const;
    long long to_integer(std::string_view token) const;
    std::size_t position() const { return pos_; }

private:
    const std::string& path_;
    const std::string& text_;
    std::size_t pos_ = 0;
    int line_ = 0;
};

// Splits `line` at spaces and tabs (and drops a trailing '\r').
std::vector<std::string_view> split_tokens(std::string_view line);

// Reads little- or big-endian values with bounds checks; errors are "FILE: what".
class ByteCursor {
public:
    // `start` may lie past the end (a text header that ends without a newline): no bytes are left then.
    ByteCursor(const std::string& path, const std::string& bytes, std::size_t start = 0)
        : path_(path), bytes_(bytes), pos_(std::min(start, bytes.size())) {}
    std::size_t position() const { return pos_; }
    std::size_t bytes_left() const { return bytes_.size() - pos_; }
    void skip(std::size_t n);
    [[noreturn]] void fail(const std::string& what) const;
    template <class T>
    T read(bool big_endian = false) {
        need(sizeof(T));
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, bytes_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        if (big_endian) {
            for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(raw[i], raw[sizeof(T) - 1 - i]);
        }
        T value;
        std::memcpy(&value, raw, sizeof(T));
        return value;
    }

private:
    void need(std::size_t n);
    const std::string& path_;
    const std::string& bytes_;
    std::size_t pos_;
};

// Appends little-endian values to a byte string (the host is little-endian on
// every platform vfsd targets; static_asserted in the .cpp).
template <class T>
void put_le(std::string& out, T value) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    out.append(raw, sizeof(T));
}

// `token` in quotes for a message: at most 32 characters, non-printable ones as '?'.
std::string quoted(std::string_view token);

// Fan-triangulates the polygon `corners` (at least 3 vertices) into `triangles`.
void append_fan(std::vector<Triangle>& triangles, const std::vector<std::uint32_t>& corners);

// Shortest decimal text that reads back as exactly `value`; "x y z" of a position;
// "a b c" of a triangle's indices plus `base`.
std::string format_number(double value);
std::string format_position(const Vec3& p);
std::string format_triangle(const Triangle& t, std::uint32_t base);

// Checks a binary file's mesh: finite positions and scalar, indices in range, and
// at least one triangle. Throws InputError "FILE: what".
void check_mesh(const std::string& path, const TriangleMesh& mesh);

// Text formats count their vertices while reading; this checks the triangles.
void require_triangles(const TextCursor& cursor, const TriangleMesh& mesh);

TriangleMesh read_obj(const std::string& path, const std::string& text);
TriangleMesh read_off(const std::string& path, const std::string& text);
TriangleMesh read_ply(const std::string& path, const std::string& bytes);
TriangleMesh read_stl(const std::string& path, const std::string& bytes);
// `external_files`: a .gltf may load buffers from files next to `path`; false when
// reading from memory (only embedded data: URIs then).
TriangleMesh read_gltf(const std::string& path, const std::string& bytes, bool binary, bool external_files = true);

std::string write_obj(const TriangleMesh& mesh);
std::string write_off(const TriangleMesh& mesh);
std::string write_ply(const TriangleMesh& mesh, const WriteOptions& options);
std::string write_glb(const TriangleMesh& mesh, const WriteOptions& options);

}  // namespace vfsd::io
