// glTF reading: node transforms, scenes, strips and fans, seams.

#include <catch2/catch.hpp>

#include "base/error.h"
#include "io/mesh_file.h"
#include "test_io_support.h"

using namespace vfsd;
using vfsd::test::ScratchDir;
using vfsd::test::write_bytes;

namespace {

// The binary chunk the test files share: view 0 a unit square (0,0)(1,0)(1,1)(0,1),
// view 1 the same square in strip order (0,0)(1,0)(0,1)(1,1), view 2 uint16 indices 0 1 2.
std::string square_buffer() {
    std::string bin;
    const float fan[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, strip[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    for (const auto* square : {fan, strip}) {
        for (int v = 0; v < 4; ++v) {
            for (float c : {square[v][0], square[v][1], 0.0f}) test::append_value(bin, c);
        }
    }
    for (std::uint16_t i : {0, 1, 2}) test::append_value(bin, i);
    return bin;
}

// A GLB over square_buffer(); `scene_part` gives "scene", "scenes", "nodes" and "meshes".
std::string square_glb(const std::string& scene_part) {
    const std::string json = R"({"asset":{"version":"2.0"},)" + scene_part + R"(,
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},
                   {"bufferView":2,"componentType":5123,"count":3,"type":"SCALAR"},
                   {"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"},
                   {"bufferView":0,"componentType":5126,"count":4,"type":"VEC3"}],
      "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":48},
                     {"buffer":0,"byteOffset":96,"byteLength":6}],
      "buffers":[{"byteLength":102}]})";
    return test::make_glb(json, square_buffer());
}

Vec3 face_normal(const TriangleMesh& m, const Triangle& t) {
    return glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
}

const char* kTransformedScenes = R"("scene":0,
      "scenes":[{"nodes":[0]},{"nodes":[2]}],
      "nodes":[{"translation":[10,0,0],"children":[1]},
               {"mesh":0,"scale":[2,2,2],"rotation":[0,0,0.7071067811865476,0.7071067811865476]},
               {"mesh":0,"matrix":[-1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}])";

}  // namespace

TEST_CASE("glTF applies the node transforms of the default scene", "[io][gltf]") {
    ScratchDir dir;
    write_bytes(dir.file("t.glb"), square_glb(kTransformedScenes));
    const TriangleMesh m = read_mesh_file(dir.file("t.glb")).mesh;
    REQUIRE(m.vertex_count() == 3);  // scene 1 is not the default
    // world = translate(10,0,0) * rotate_z(90 deg) * scale(2): (x, y) -> (10 - 2y, 2x).
    const Vec3 expected[3] = {Vec3(10, 0, 0), Vec3(10, 2, 0), Vec3(8, 2, 0)};
    for (int v = 0; v < 3; ++v) {
        CHECK(m.positions[v].x == Approx(expected[v].x).margin(1e-12));
        CHECK(m.positions[v].y == Approx(expected[v].y).margin(1e-12));
        CHECK(m.positions[v].z == Approx(expected[v].z).margin(1e-12));
    }
    CHECK(face_normal(m, m.triangles[0]).z > 0.0);
}

TEST_CASE("without a default scene every scene is read, and mirrors keep the outside out", "[io][gltf]") {
    std::string part = kTransformedScenes;
    part.erase(0, part.find("\"scenes\""));  // drop "scene":0
    ScratchDir dir;
    write_bytes(dir.file("all.glb"), square_glb(part));
    const TriangleMesh m = read_mesh_file(dir.file("all.glb")).mesh;
    REQUIRE(m.triangle_count() == 2);
    CHECK(m.vertex_count() == 6);
    for (const Triangle& t : m.triangles) CHECK(face_normal(m, t).z > 0.0);
}

TEST_CASE("glTF strips and fans are triangulated and seams between primitives welded", "[io][gltf]") {
    ScratchDir dir;
    write_bytes(dir.file("sf.glb"), square_glb(R"("scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":2},"mode":5},{"attributes":{"POSITION":3},"mode":6},
                               {"attributes":{"POSITION":3},"mode":1}]}])"));
    const MeshFile file = read_mesh_file(dir.file("sf.glb"));
    CHECK(file.file_vertex_count() == 8);  // the LINES primitive is skipped
    CHECK(file.mesh.vertex_count() == 4);
    REQUIRE(file.mesh.triangle_count() == 4);
    // As stored, every triangle of both primitives faces +z.
    const TriangleMesh stored = to_file_layout(file, file.mesh);
    for (const Triangle& t : stored.triangles) CHECK(face_normal(stored, t).z == Approx(1.0));
    // Welded, the two primitives cover the square twice and close into a flat
    // pillow, which welding winds consistently (io/mesh_file.h): one sheet up, one down.
    CHECK(file.turned_triangles == 2);
    int up = 0;
    for (const Triangle& t : file.mesh.triangles) up += face_normal(file.mesh, t).z > 0.0;
    CHECK(up == 2);
}

TEST_CASE("glTF accessors that reach beyond their buffer are refused", "[io][gltf]") {
    ScratchDir dir;
    std::string glb = square_glb(R"("scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":3},"indices":1}]}])");
    const std::string needle = R"("count":4,"type":"VEC3"}])";
    glb.replace(glb.find(needle), needle.size(), R"("count":9,"type":"VEC3"}])");
    write_bytes(dir.file("far.glb"), glb);
    CHECK_THROWS_WITH(read_mesh_file(dir.file("far.glb")), Catch::Contains("far.glb: ") && Catch::Contains("beyond"));
}
