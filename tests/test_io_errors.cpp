// Malformed files: every one gives exactly one InputError line naming the file
// (and, for text formats, the line), never a crash, a hang or a huge allocation.

#include <catch2/catch.hpp>

#include <limits>
#include <random>

#include "base/error.h"
#include "io/mesh_file.h"
#include "test_io_support.h"

using namespace vfsd;
using vfsd::test::append_value;
using vfsd::test::read_bytes;
using vfsd::test::ScratchDir;
using vfsd::test::write_bytes;

namespace {

// Reads `content` saved as `name` and returns the InputError message ("" if none was thrown).
std::string read_error(const ScratchDir& dir, const std::string& name, const std::string& content) {
    write_bytes(dir.file(name), content);
    try {
        read_mesh_file(dir.file(name));
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// The message must be one line starting with "PATH:LINE: " (line > 0 for text formats) or "PATH: ".
void check_message(const ScratchDir& dir, const std::string& name, const std::string& content, int line, const char* words) {
    CAPTURE(name, content.substr(0, 200));
    const std::string message = read_error(dir, name, content);
    CAPTURE(message);
    const std::string prefix = dir.file(name) + (line > 0 ? ":" + std::to_string(line) + ": " : ": ");
    CHECK(message.rfind(prefix, 0) == 0);
    CHECK(message.find('\n') == std::string::npos);
    CHECK(message.find(words) != std::string::npos);
}

std::string ply_header(const char* format, long long vertices, long long faces) {
    return std::string("ply\nformat ") + format + " 1.0\nelement vertex " + std::to_string(vertices) +
           "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(faces) +
           "\nproperty list uchar int vertex_indices\nend_header\n";
}

}  // namespace

TEST_CASE("malformed OBJ files name the file and the line", "[io][errors]") {
    ScratchDir dir;
    check_message(dir, "a.obj", "v 0 0 0\nv 1 0 0\nf 1 2 5\n", 3, "out of range");
    check_message(dir, "b.obj", "v 0 0 0\nv 1 zero 0\n", 2, "expected a number");
    check_message(dir, "c.obj", "v 0 0 0\nv 1 nan 0\n", 2, "not a finite number");
    check_message(dir, "d.obj", "v 0 0 0\nv 1 0 inf\n", 2, "not a finite number");
    check_message(dir, "e.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "index 0");
    check_message(dir, "f.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "at least three");
    check_message(dir, "g.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 4, "out of range");
    check_message(dir, "h.obj", "v 0 0 0\n", 1, "without any triangle");
    check_message(dir, "i.obj", "", 0, "empty file");
    check_message(dir, "j.obj", std::string("\x7f\x45LF\x01\x02\0\0v x", 11), 1, "without any triangle");
}

TEST_CASE("malformed OFF files name the file and the line", "[io][errors]") {
    ScratchDir dir;
    check_message(dir, "a.off", "OFF\n8 1 0\n0 0 0\n1 0 0\n0 1 0\n", 5, "file ends after 3 of 8 vertices");
    check_message(dir, "b.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", 6, "out of range");
    check_message(dir, "c.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", 6, "file ends after 1 of 2 faces");
    check_message(dir, "d.off", "OFF\n999999999999 1 0\n0 0 0\n", 3, "file ends after 1 of 999999999999");
    check_message(dir, "e.off", "PLY\n3 1 0\n", 1, "not an OFF file");
    check_message(dir, "f.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", 6, "declares 4 vertices but lists 3");
    check_message(dir, "g.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 -nan\n3 0 1 2\n", 5, "not a finite number");
    check_message(dir, "h.off", "OFF\n-3 1 0\n", 2, "negative count");
}

TEST_CASE("malformed PLY files: text header lines, binary body offsets", "[io][errors]") {
    ScratchDir dir;
    const std::string ascii = ply_header("ascii", 3, 1);
    check_message(dir, "b.ply", ascii + "0 0 0\n1 0 0\n", 11, "unexpected end of file");
    check_message(dir, "c.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n", 4, "no end_header");
    check_message(dir, "d.ply", "plyx\n", 1, "not a PLY file");
    check_message(dir, "e.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quaternion x\nend_header\n", 4, "unknown property type");
    std::string binary = ply_header("binary_little_endian", 3, 1);
    for (float c : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f}) append_value(binary, c);
    check_message(dir, "f.ply", binary, 0, "declares 3 vertex elements but only 32 bytes");
    std::string truncated_face = binary;
    append_value(truncated_face, 1.0f);
    append_value(truncated_face, std::uint8_t{3});
    for (std::int32_t i : {0, 1}) append_value(truncated_face, i);
    check_message(dir, "f2.ply", truncated_face, 0, "unexpected end of file");
    append_value(binary, std::numeric_limits<float>::quiet_NaN());
    append_value(binary, std::uint8_t{3});
    for (std::int32_t i : {0, 1, 2}) append_value(binary, i);
    check_message(dir, "g.ply", binary, 0, "vertex 2 has a non-finite coordinate");
    // A declared count the file cannot hold is refused before anything is allocated.
    check_message(dir, "h.ply", ply_header("binary_little_endian", 4000000000000LL, 1) + "tiny", 0, "declares 4000000000000 vertex");
    check_message(dir, "i.ply", ply_header("binary_little_endian", 3, 0) + std::string(36, '\0'), 0, "no triangles");
}

TEST_CASE("the ascii PLY error names the body line", "[io][errors]") {
    ScratchDir dir;
    // The header has 9 lines; the face is on line 13.
    check_message(dir, "a.ply", ply_header("ascii", 3, 1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", 13, "out of range");
}

TEST_CASE("malformed STL files are refused", "[io][errors]") {
    ScratchDir dir;
    const std::string good = test::binary_stl(test::unit_cube());
    check_message(dir, "a.stl", good.substr(0, good.size() - 7), 0, "does not match");
    check_message(dir, "b.stl", "abc", 0, "too short");
    check_message(dir, "c.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n", 6, "loop has 2 vertices");
    check_message(dir, "d.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n", 5, "inside a loop");
    check_message(dir, "e.stl", "solid x\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 inf\nendloop\n", 5, "not a finite number");
    check_message(dir, "f.stl", "solid x\nendsolid x\n", 2, "without any triangle");
    std::string nan = good;
    const float bad = std::numeric_limits<float>::infinity();
    std::memcpy(&nan[84 + 12], &bad, 4);
    check_message(dir, "g.stl", nan, 0, "vertex 0 has a non-finite coordinate");
}

TEST_CASE("malformed glTF files are refused", "[io][errors]") {
    ScratchDir dir;
    check_message(dir, "a.gltf", "{ not json", 0, "");
    check_message(dir, "b.glb", "glTF\x02\0\0\0garbage", 0, "");
    check_message(dir, "c.gltf", R"({"asset":{"version":"2.0"},"meshes":[]})", 0, "no triangles");
    check_message(dir, "d.gltf", R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"children":[0]}]})", 0, "");
    check_message(dir, "e.glb", "", 0, "empty file");
}

TEST_CASE("unknown extensions and missing files", "[io][errors]") {
    ScratchDir dir;
    check_message(dir, "a.xyz", "v 0 0 0", 0, "unknown mesh format '.xyz'");
    CHECK_THROWS_AS(read_mesh_file(dir.file("missing.obj")), IoError);
    CHECK_THROWS_AS(load_mesh("builtin:box:x"), InputError);
    CHECK_THROWS_AS(load_mesh("builtin:box:-1"), InputError);
}

TEST_CASE("corrupted files of every format are read or refused with InputError, never crash", "[io][errors]") {
    ScratchDir dir;
    const TriangleMesh grid = test::wavy_grid(3);
    std::mt19937 random(12345);  // fixed seed: the same corruptions every run
    for (const char* ext : {"obj", "off", "ply", "glb", "stl"}) {
        const std::string clean = dir.file(std::string("clean.") + ext), path = dir.file(std::string("bad.") + ext);
        if (std::string(ext) == "stl") write_bytes(clean, test::binary_stl(grid));
        else write_mesh_file(clean, grid);
        const std::string bytes = read_bytes(clean);
        int refused = 0;
        for (int trial = 0; trial < 300; ++trial) {
            std::string corrupt = bytes;
            if (trial % 3 == 0) corrupt.resize(random() % corrupt.size());  // truncate
            const int flips = 1 + static_cast<int>(random() % 4);
            for (int k = 0; k < flips && !corrupt.empty(); ++k) corrupt[random() % corrupt.size()] = static_cast<char>(random());
            write_bytes(path, corrupt);
            try {
                const MeshFile file = read_mesh_file(path);
                CHECK(file.mesh.triangle_count() > 0);
            } catch (const InputError& e) {
                ++refused;
                CHECK(std::string(e.what()).rfind(path, 0) == 0);
            }
        }
        CAPTURE(ext);
        CHECK(refused > 0);
    }
}
