// Write-then-read round trips in every written format, and hand-made PLY variants.

#include <catch2/catch.hpp>

#include "io/mesh_file.h"
#include "mesh/geometry.h"
#include "test_io_support.h"

using namespace vfsd;
using vfsd::test::ScratchDir;
using vfsd::test::write_bytes;

namespace {

// The largest coordinate difference relative to the coordinate's size.
double max_relative_error(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double worst = 0.0;
    for (std::size_t v = 0; v < a.size(); ++v) {
        for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(a[v][k] - b[v][k]) / std::max(1.0, std::abs(a[v][k])));
    }
    return worst;
}

}  // namespace

TEST_CASE("every written format reads back with the same connectivity", "[io]") {
    ScratchDir dir;
    const TriangleMesh grid = test::wavy_grid(6);
    for (const char* ext : {"obj", "off", "ply", "glb", "PLY", "Obj"}) {
        CAPTURE(ext);
        const std::string path = dir.file(std::string("grid.") + ext);
        write_mesh_file(path, grid);
        const MeshFile file = read_mesh_file(path);
        REQUIRE(file.mesh.vertex_count() == grid.vertex_count());
        CHECK(file.mesh.triangles == grid.triangles);
        CHECK(file.layout_is_identity());
        // float32 storage (PLY, GLB) keeps about 7 digits; text formats are exact.
        const bool text = file.format == "obj" || file.format == "off";
        CHECK(max_relative_error(file.mesh.positions, grid.positions) <= (text ? 0.0 : 6e-8));
    }
}

TEST_CASE("PLY and GLB carry the per-vertex scalar; PLY can store doubles", "[io]") {
    ScratchDir dir;
    const TriangleMesh grid = test::wavy_grid(4);
    for (const char* name : {"s.ply", "s.glb"}) {
        write_mesh_file(dir.file(name), grid);
        const TriangleMesh back = read_mesh_file(dir.file(name)).mesh;
        REQUIRE(back.has_scalar());
        for (std::size_t v = 0; v < grid.vertex_count(); ++v) CHECK(back.scalar[v] == Approx(grid.scalar[v]).margin(1e-7));
    }
    WriteOptions exact;
    exact.double_positions = true;
    write_mesh_file(dir.file("d.ply"), grid, exact);
    const TriangleMesh back = read_mesh_file(dir.file("d.ply")).mesh;
    CHECK(back.positions == grid.positions);
    CHECK(back.scalar == grid.scalar);
    WriteOptions no_scalar;
    no_scalar.write_scalar = false;
    write_mesh_file(dir.file("n.ply"), grid, no_scalar);
    CHECK_FALSE(read_mesh_file(dir.file("n.ply")).mesh.has_scalar());
}

TEST_CASE("ascii and big-endian PLY: polygons are fan-triangulated, extra elements skipped", "[io]") {
    ScratchDir dir;
    const std::string header_tail =
        "element vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty float s\n"
        "element face 1\nproperty list uchar int vertex_indices\nelement edge 1\nproperty int a\nproperty int b\nend_header\n";
    write_bytes(dir.file("a.ply"), "ply\nformat ascii 1.0\ncomment quad\n" + header_tail +
                                       "0 0 0 255 0.5\n1 0 0 0 1.5\n1 1 0 0 2.5\n0 1 0 0 3.5\n4 0 1 2 3\n0 1\n");
    std::string big = "ply\nformat binary_big_endian 1.0\n" + header_tail;
    const float xy[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int v = 0; v < 4; ++v) {
        for (float c : {xy[v][0], xy[v][1], 0.0f}) test::append_value(big, c, true);
        test::append_value(big, std::uint8_t{7}, true);
        test::append_value(big, 0.5f + v, true);
    }
    test::append_value(big, std::uint8_t{4});
    for (std::int32_t i : {0, 1, 2, 3}) test::append_value(big, i, true);
    test::append_value(big, std::int32_t{0}, true);
    test::append_value(big, std::int32_t{1}, true);
    write_bytes(dir.file("b.ply"), big);
    for (const char* name : {"a.ply", "b.ply"}) {
        CAPTURE(name);
        const TriangleMesh m = read_mesh_file(dir.file(name)).mesh;
        REQUIRE(m.vertex_count() == 4);
        CHECK(m.triangles == std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}});
        CHECK(m.positions[2] == Vec3(1, 1, 0));
        CHECK(m.scalar == std::vector<double>{0.5, 1.5, 2.5, 3.5});
    }
}

TEST_CASE("OBJ reads v/vt/vn corners, negative indices and polygons, ignoring other statements", "[io]") {
    ScratchDir dir;
    write_bytes(dir.file("q.obj"),
                "# a quad and a triangle\nmtllib x.mtl\no quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
                "usemtl m\ns off\nf 1/1/1 2/1/1 3//1 4/1\nv 2 1 0\nf -4 -1 -3\nl 1 2\n");
    const MeshFile file = read_mesh_file(dir.file("q.obj"));
    CHECK(file.mesh.vertex_count() == 5);
    CHECK(file.mesh.triangles == std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}, {1, 4, 2}});
    CHECK(file.layout_is_identity());
}

TEST_CASE("OFF reads headers with counts, comments, colours and polygons", "[io]") {
    ScratchDir dir;
    write_bytes(dir.file("c.off"), "COFF 4 1 0\n# comment\n0 0 0 255 0 0 255\n1 0 0 0 0 0 255\n\n1 1 0 0 0 0 255\n0 1 0 0 0 0 255\n4 3 2 1 0 1 0 0\n");
    const TriangleMesh m = read_mesh_file(dir.file("c.off")).mesh;
    CHECK(m.vertex_count() == 4);
    CHECK(m.triangles == std::vector<Triangle>{{3, 2, 1}, {3, 1, 0}});
}

TEST_CASE("a closed mesh keeps its volume through every format", "[io]") {
    ScratchDir dir;
    const TriangleMesh cube = test::unit_cube();
    for (const char* name : {"c.obj", "c.off", "c.ply", "c.glb"}) {
        write_mesh_file(dir.file(name), cube);
        const TriangleMesh m = read_mesh_file(dir.file(name)).mesh;
        CHECK(signed_volume(m.positions, m.triangles) == Approx(1.0).epsilon(1e-12));
    }
}
