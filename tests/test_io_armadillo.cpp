// CGAL's armadillo through OBJ -> PLY -> GLB -> OFF keeps its counts, its
// triangles and its positions within float precision. Skipped without the data
// (scripts/get-cgal-meshes).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "io/mesh_file.h"
#include "test_io_support.h"

using namespace vfsd;

TEST_CASE("armadillo round-trips through every writer", "[io][cgal]") {
    const std::string source = std::string(VFSD_SOURCE_DIR) + "/assets/cgal/armadillo.off";
    if (!std::filesystem::exists(source)) {
        WARN("skipped: " << source << " is absent (run scripts/get-cgal-meshes)");
        return;
    }
    test::ScratchDir dir;
    const TriangleMesh original = load_mesh(source);
    std::string previous = source;
    for (const char* format : {"obj", "ply", "glb", "off"}) {
        const std::string next = dir.file(std::string("armadillo.") + format);
        write_mesh_file(next, load_mesh(previous));
        previous = next;
    }
    const TriangleMesh back = load_mesh(previous);
    REQUIRE(back.vertex_count() == 26002);
    REQUIRE(back.triangle_count() == 52000);
    CHECK(back.triangles == original.triangles);
    double worst = 0.0;
    for (std::size_t v = 0; v < original.vertex_count(); ++v)
        for (int k = 0; k < 3; ++k)
            worst = std::max(worst, std::abs(back.positions[v][k] - original.positions[v][k]) /
                                        std::max(std::abs(original.positions[v][k]), 1e-3));
    CHECK(worst < 1.2e-7);  // float32 rounding: 2^-24 relative, twice
}
