// `vfsd convert`: exit codes 0 (done), 1 (bad input, refused overwrite), 2 (usage).

#include <sys/wait.h>

#include <catch2/catch.hpp>

#include <cstdlib>

#include "io/mesh_file.h"
#include "test_io_support.h"

using namespace vfsd;
using vfsd::test::read_bytes;
using vfsd::test::ScratchDir;
using vfsd::test::write_bytes;

namespace {

// Runs `vfsd convert ARGS` with stdout and stderr saved in `dir`; returns the exit code.
int convert(const ScratchDir& dir, const std::string& args) {
    const std::string command = std::string("'") + VFSD_CLI_PATH + "' convert " + args + " >'" + dir.file("stdout.txt") + "' 2>'" +
                                dir.file("stderr.txt") + "'";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string quoted(const std::string& path) { return "'" + path + "'"; }

}  // namespace

TEST_CASE("vfsd convert writes the welded mesh and refuses unsafe outputs", "[io][cli]") {
    ScratchDir dir;
    const std::string stl = dir.file("cube.stl"), off = dir.file("cube.off");
    write_bytes(stl, test::binary_stl(test::unit_cube()));
    REQUIRE(convert(dir, quoted(stl) + " " + quoted(off)) == 0);
    CHECK(read_mesh_file(off).mesh.vertex_count() == 8);
    CHECK(read_mesh_file(off).layout_is_identity());

    // An existing output needs --force; the input is never the output.
    const std::string before = read_bytes(off);
    CHECK(convert(dir, quoted(stl) + " " + quoted(off)) == 1);
    CHECK(read_bytes(dir.file("stderr.txt")).find("--force") != std::string::npos);
    CHECK(convert(dir, quoted(off) + " " + quoted(dir.path().string() + "/./cube.off") + " --force") == 1);
    CHECK(read_bytes(dir.file("stderr.txt")).find("same file") != std::string::npos);
    CHECK(read_bytes(off) == before);
    CHECK(convert(dir, quoted(stl) + " " + quoted(off) + " --force --keep-layout") == 0);
    CHECK(read_mesh_file(off).file_vertex_count() == 36);
}

TEST_CASE("vfsd convert reports bad input in one line with exit code 1, bad usage with 2", "[io][cli]") {
    ScratchDir dir;
    write_bytes(dir.file("bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    CHECK(convert(dir, quoted(dir.file("bad.obj")) + " " + quoted(dir.file("out.ply"))) == 1);
    const std::string err = read_bytes(dir.file("stderr.txt"));
    CHECK(err.find(dir.file("bad.obj") + ":3: ") != std::string::npos);
    CHECK(std::count(err.begin(), err.end(), '\n') == 1);
    CHECK_FALSE(std::filesystem::exists(dir.file("out.ply")));
    CHECK(convert(dir, quoted(dir.file("missing.off")) + " " + quoted(dir.file("out.ply"))) == 1);
    CHECK(convert(dir, quoted(dir.file("bad.obj"))) == 2);
    CHECK(convert(dir, "builtin:box " + quoted(dir.file("out.ply")) + " --colour red") == 2);
    CHECK(convert(dir, "builtin:box:2 " + quoted(dir.file("out.ply"))) == 0);
    CHECK(read_mesh_file(dir.file("out.ply")).mesh.triangle_count() > 0);
    CHECK(convert(dir, "builtin:box:2 " + quoted(dir.file("sub.ply")) + " --subdivide -1") == 2);
    CHECK(convert(dir, "builtin:box:2 " + quoted(dir.file("sub.ply")) + " --subdivide 1.5") == 2);
    CHECK(convert(dir, "builtin:box:2 " + quoted(dir.file("sub.ply")) + " --subdivide 1 --keep-layout") == 2);
    CHECK_FALSE(std::filesystem::exists(dir.file("sub.ply")));
    REQUIRE(convert(dir, "builtin:box:2 " + quoted(dir.file("sub.ply")) + " --subdivide 2") == 0);
    CHECK(read_mesh_file(dir.file("sub.ply")).mesh.triangle_count() ==
          16 * read_mesh_file(dir.file("out.ply")).mesh.triangle_count());
}
