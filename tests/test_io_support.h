#pragma once
// Shared helpers of the file-format tests: small meshes, a scratch folder, and
// byte builders for hand-made files.

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "mesh/triangle_mesh.h"

namespace vfsd::test {

// A unit cube of 8 vertices and 12 outward-facing triangles.
inline TriangleMesh unit_cube() {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i) m.positions.push_back(Vec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
    const unsigned q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (auto& f : q) {
        m.triangles.push_back({f[0], f[1], f[2]});
        m.triangles.push_back({f[0], f[2], f[3]});
    }
    return m;
}

// An open n x n grid of quads in the plane z = 0.1 x y, with irregular coordinates
// (not exactly representable in float) and a scalar per vertex.
inline TriangleMesh wavy_grid(unsigned n) {
    TriangleMesh m;
    for (unsigned j = 0; j <= n; ++j) {
        for (unsigned i = 0; i <= n; ++i) {
            const double x = i / 3.0 + 0.01 * j, y = j / 7.0;
            m.positions.push_back(Vec3(x, y, 0.1 * x * y));
            m.scalar.push_back(std::sin(0.3 * i + j));
        }
    }
    for (unsigned j = 0; j < n; ++j) {
        for (unsigned i = 0; i < n; ++i) {
            const unsigned a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            m.triangles.push_back({a, b, d});
            m.triangles.push_back({a, d, c});
        }
    }
    return m;
}

// A fresh folder under the system's temporary folder, removed with its contents.
class ScratchDir {
public:
    ScratchDir() {
        static int counter = 0;
        path_ = std::filesystem::temp_directory_path() /
                ("vfsd_io_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;

    std::string file(const std::string& name) const { return (path_ / name).string(); }
    const std::filesystem::path& path() const { return path_; }
    // The names of the entries in the folder.
    std::size_t entry_count() const {
        std::size_t n = 0;
        for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(path_)) ++n;
        return n;
    }

private:
    std::filesystem::path path_;
};

inline void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

inline std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

template <class T>
void append_value(std::string& out, T value, bool big_endian = false) {
    char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    if (big_endian) std::reverse(raw, raw + sizeof(T));
    out.append(raw, sizeof(T));
}

// A binary STL of `mesh`: three corners per triangle, as STL stores them.
inline std::string binary_stl(const TriangleMesh& mesh) {
    std::string out(80, ' ');
    append_value(out, static_cast<std::uint32_t>(mesh.triangle_count()));
    for (const Triangle& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) append_value(out, 0.0f);
        for (int c = 0; c < 3; ++c) {
            for (int k = 0; k < 3; ++k) append_value(out, static_cast<float>(mesh.positions[t[c]][k]));
        }
        append_value(out, std::uint16_t{0});
    }
    return out;
}

// A GLB from its JSON text and binary chunk.
inline std::string make_glb(std::string json, std::string bin) {
    json.resize((json.size() + 3) / 4 * 4, ' ');
    bin.resize((bin.size() + 3) / 4 * 4, '\0');
    std::string out;
    append_value(out, 0x46546C67u);
    append_value(out, 2u);
    append_value(out, static_cast<std::uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
    append_value(out, static_cast<std::uint32_t>(json.size()));
    append_value(out, 0x4E4F534Au);
    out += json;
    append_value(out, static_cast<std::uint32_t>(bin.size()));
    append_value(out, 0x004E4942u);
    return out + bin;
}

}  // namespace vfsd::test
