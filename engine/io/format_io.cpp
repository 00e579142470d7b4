#include "io/format_io.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "base/error.h"

namespace vfsd::io {

// put_le and ByteCursor copy host bytes: the host must be little-endian (x86, ARM, wasm).
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "vfsd's binary file code assumes a little-endian host");

std::string read_file_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError(path + ": cannot open: " + std::strerror(errno));
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw IoError(path + ": read failed: " + std::strerror(errno));
    return std::move(buffer).str();
}

bool TextCursor::next_line(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string::npos) end = text_.size();
    line = std::string_view(text_).substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    ++line_;
    return true;
}

void TextCursor::fail(const std::string& what) const {
    throw InputError(path_ + ":" + std::to_string(line_) + ": " + what);
}

double TextCursor::to_double(std::string_view token) const {
    // The token lies inside the NUL-terminated file text, so strtod stops at its end.
    char* end = nullptr;
    const double value = std::strtod(token.data(), &end);
    if (token.empty() || end != token.data() + token.size()) fail("expected a number, got " + quoted(token));
    if (!std::isfinite(value)) fail("coordinate " + quoted(token) + " is not a finite number");
    return value;
}

long long TextCursor::to_integer(std::string_view token) const {
    long long value = 0;
    const char* end = token.data() + token.size();
    const auto result = std::from_chars(token.data(), end, value);
    if (token.empty() || result.ec != std::errc() || result.ptr != end) {
        fail("expected an integer, got " + quoted(token));
    }
    return value;
}

std::vector<std::string_view> split_tokens(std::string_view line) {
    std::vector<std::string_view> tokens;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        std::size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
        if (j > i) tokens.push_back(line.substr(i, j - i));
        i = j;
    }
    return tokens;
}

void ByteCursor::skip(std::size_t n) {
    need(n);
    pos_ += n;
}

void ByteCursor::need(std::size_t n) {
    if (n > bytes_left()) fail("unexpected end of file at byte " + std::to_string(bytes_.size()));
}

void ByteCursor::fail(const std::string& what) const { throw InputError(path_ + ": " + what); }

std::string quoted(std::string_view token) {
    std::string text(token.substr(0, 32));
    for (char& c : text) c = (c >= 32 && c < 127) ? c : '?';
    return "'" + text + (token.size() > 32 ? "...'" : "'");
}

void append_fan(std::vector<Triangle>& triangles, const std::vector<std::uint32_t>& corners) {
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) triangles.push_back({corners[0], corners[k], corners[k + 1]});
}

std::string format_number(double value) {
    char text[32];
    // 15 significant digits are shorter and usually exact; fall back to 17 (always exact).
    std::snprintf(text, sizeof text, "%.15g", value);
    if (std::strtod(text, nullptr) != value) std::snprintf(text, sizeof text, "%.17g", value);
    return text;
}

std::string format_position(const Vec3& p) { return format_number(p.x) + " " + format_number(p.y) + " " + format_number(p.z); }

std::string format_triangle(const Triangle& t, std::uint32_t base) {
    return std::to_string(t[0] + base) + " " + std::to_string(t[1] + base) + " " + std::to_string(t[2] + base);
}

void check_mesh(const std::string& path, const TriangleMesh& mesh) {
    for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
        const Vec3& p = mesh.positions[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            throw InputError(path + ": vertex " + std::to_string(v) + " has a non-finite coordinate");
        }
    }
    for (std::size_t v = 0; v < mesh.scalar.size(); ++v) {
        if (!std::isfinite(mesh.scalar[v])) throw InputError(path + ": vertex " + std::to_string(v) + " has a non-finite scalar");
    }
    const std::size_t n = mesh.positions.size();
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        if (tri[0] >= n || tri[1] >= n || tri[2] >= n) {
            throw InputError(path + ": triangle " + std::to_string(t) + " refers to a vertex beyond the " + std::to_string(n) +
                             " vertices");
        }
    }
    if (mesh.triangles.empty()) throw InputError(path + ": contains no triangles");
}

void require_triangles(const TextCursor& cursor, const TriangleMesh& mesh) {
    if (mesh.triangles.empty()) cursor.fail("file ends without any triangle");
}

}  // namespace vfsd::io
