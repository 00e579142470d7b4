// Atomic writes: no temporary file is left behind and a failed write leaves the
// existing file as it was.

#include <catch2/catch.hpp>

#include "base/error.h"
#include "io/mesh_file.h"
#include "test_io_support.h"

using namespace vfsd;
using vfsd::test::read_bytes;
using vfsd::test::ScratchDir;
using vfsd::test::write_bytes;

TEST_CASE("a successful write leaves only the target in the folder", "[io][atomic]") {
    ScratchDir dir;
    for (const char* name : {"m.obj", "m.off", "m.ply", "m.glb"}) write_mesh_file(dir.file(name), test::unit_cube());
    CHECK(dir.entry_count() == 4);
    // Replacing an existing file also leaves nothing else behind.
    write_mesh_file(dir.file("m.ply"), test::wavy_grid(3));
    CHECK(dir.entry_count() == 4);
    CHECK(read_mesh_file(dir.file("m.ply")).mesh.vertex_count() == 16);
}

TEST_CASE("a failed write does not touch the existing file", "[io][atomic]") {
    ScratchDir dir;
    const std::string path = dir.file("keep.ply");
    write_bytes(path, "original bytes");
    // An invalid mesh (index out of range) is refused before anything is written.
    TriangleMesh bad = test::unit_cube();
    bad.triangles.push_back({0, 1, 8});
    CHECK_THROWS_AS(write_mesh_file(path, bad), InputError);
    TriangleMesh empty;
    CHECK_THROWS_AS(write_mesh_file(path, empty), InputError);
    CHECK_THROWS_AS(write_mesh_file(dir.file("keep.stl"), test::unit_cube()), InputError);
    CHECK(read_bytes(path) == "original bytes");
    // The rename fails (the target is a folder): the temporary file is removed again.
    std::filesystem::create_directory(dir.file("folder.obj"));
    CHECK_THROWS_AS(write_mesh_file(dir.file("folder.obj"), test::unit_cube()), IoError);
    CHECK(std::filesystem::is_directory(dir.file("folder.obj")));
    // A folder that does not exist: nothing can be created.
    CHECK_THROWS_AS(write_mesh_file(dir.file("no/such/folder.obj"), test::unit_cube()), IoError);
    CHECK(dir.entry_count() == 2);
    CHECK(read_bytes(path) == "original bytes");
}

TEST_CASE("write_file_atomically replaces the content in one step", "[io][atomic]") {
    ScratchDir dir;
    const std::string path = dir.file("data.bin");
    write_file_atomically(path, std::string(100000, 'a'));
    write_file_atomically(path, "b");
    CHECK(read_bytes(path) == "b");
    CHECK(dir.entry_count() == 1);
}
