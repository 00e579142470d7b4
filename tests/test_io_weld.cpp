// Welding of split vertices and the file-layout mapping.

#include <catch2/catch.hpp>

#include "base/error.h"
#include "io/mesh_file.h"
#include "mesh/geometry.h"
#include "mesh/vertex_rings.h"
#include "test_io_support.h"

using namespace vfsd;
using vfsd::test::ScratchDir;
using vfsd::test::write_bytes;

namespace {

// Every vertex has a closed ring: a closed 2-manifold without boundary.
bool closed_manifold(const TriangleMesh& mesh) {
    const VertexRings rings = build_vertex_rings(mesh);
    for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
        if (rings.valence(v) == 0 || !rings.is_closed(v)) return false;
    }
    return true;
}

std::string ascii_stl(const TriangleMesh& mesh) {
    std::string out = "solid cube\n";
    for (const Triangle& t : mesh.triangles) {
        out += "  facet normal 0 0 0\n    outer loop\n";
        for (int c = 0; c < 3; ++c) {
            const Vec3& p = mesh.positions[t[c]];
            out += "      vertex " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
        }
        out += "    endloop\n  endfacet\n";
    }
    return out + "endsolid cube\n";
}

}  // namespace

TEST_CASE("STL is welded into a closed manifold with the right vertex count", "[io][weld]") {
    ScratchDir dir;
    const TriangleMesh cube = test::unit_cube();
    write_bytes(dir.file("bin.stl"), test::binary_stl(cube));
    write_bytes(dir.file("ascii.STL"), ascii_stl(cube));
    for (const char* name : {"bin.stl", "ascii.STL"}) {
        CAPTURE(name);
        const MeshFile file = read_mesh_file(dir.file(name));
        CHECK(file.file_vertex_count() == 36);
        CHECK(file.mesh.vertex_count() == 8);
        CHECK(file.mesh.triangle_count() == 12);
        CHECK_FALSE(file.layout_is_identity());
        CHECK(closed_manifold(file.mesh));
        CHECK(signed_volume(file.mesh.positions, file.mesh.triangles) == Approx(1.0));
    }
}

TEST_CASE("files without repeated positions keep their vertex order", "[io][weld]") {
    // The cube with its vertices in a scrambled order: welding must not renumber them.
    TriangleMesh cube = test::unit_cube();
    const std::uint32_t order[8] = {5, 2, 7, 0, 3, 6, 1, 4};
    TriangleMesh scrambled;
    std::vector<std::uint32_t> new_index(8);
    for (std::uint32_t i = 0; i < 8; ++i) {
        scrambled.positions.push_back(cube.positions[order[i]]);
        new_index[order[i]] = i;
    }
    for (const Triangle& t : cube.triangles) scrambled.triangles.push_back({new_index[t[0]], new_index[t[1]], new_index[t[2]]});
    ScratchDir dir;
    for (const char* name : {"s.obj", "s.off", "s.ply"}) {
        write_mesh_file(dir.file(name), scrambled);
        const MeshFile file = read_mesh_file(dir.file(name));
        CHECK(file.mesh.positions == scrambled.positions);
        CHECK(file.mesh.triangles == scrambled.triangles);
        CHECK(file.layout_is_identity());
    }
}

TEST_CASE("OBJ with repeated positions is welded; -0 and +0 are one position", "[io][weld]") {
    ScratchDir dir;
    // Two triangles of a square, each with its own copies of the shared diagonal.
    write_bytes(dir.file("split.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 0\nv -0 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 4 5 6\n");
    const MeshFile file = read_mesh_file(dir.file("split.obj"));
    CHECK(file.mesh.vertex_count() == 4);
    CHECK(file.file_to_mesh == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3});
    CHECK(file.mesh.triangles == std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}});
    const VertexRings rings = build_vertex_rings(file.mesh);
    CHECK(rings.valence(0) == 3);  // the diagonal now joins the two triangles
}

TEST_CASE("the layout mapping writes a deformed mesh back in the file's layout", "[io][weld]") {
    ScratchDir dir;
    write_bytes(dir.file("cube.stl"), test::binary_stl(test::unit_cube()));
    const MeshFile file = read_mesh_file(dir.file("cube.stl"));
    // "Deform": a shear that moves every welded vertex differently.
    TriangleMesh deformed = file.mesh;
    for (Vec3& p : deformed.positions) p += Vec3(0.25 * p.z, 0.5 * p.x, 0.0);
    const TriangleMesh layout = to_file_layout(file, deformed);
    REQUIRE(layout.vertex_count() == file.file_vertex_count());
    CHECK(layout.triangles == file.file_triangles);
    for (std::size_t i = 0; i < layout.vertex_count(); ++i) CHECK(layout.positions[i] == deformed.positions[file.file_to_mesh[i]]);
    // Written in the layout and read again, it welds to the deformed mesh.
    write_mesh_file(dir.file("layout.ply"), layout);
    const MeshFile again = read_mesh_file(dir.file("layout.ply"));
    CHECK(again.file_to_mesh == file.file_to_mesh);
    CHECK(again.mesh.triangles == file.mesh.triangles);
    CHECK(again.mesh.positions == deformed.positions);  // shear of 0/1 coordinates: exact in float
    CHECK_THROWS_AS(to_file_layout(file, test::wavy_grid(2)), InputError);
}

TEST_CASE("triangles made degenerate by welding are dropped from the welded mesh only", "[io][weld]") {
    TriangleMesh m;
    m.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 0, 0)};
    m.triangles = {{0, 1, 2}, {0, 1, 3}};
    const MeshFile file = weld_mesh(m, "test");
    CHECK(file.mesh.triangles == std::vector<Triangle>{{0, 1, 2}});
    CHECK(file.file_triangles == m.triangles);
    CHECK(to_file_layout(file, file.mesh).positions == m.positions);
}
