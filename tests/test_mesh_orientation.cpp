// Consistent winding (mesh/orientation.h): generated meshes with triangles
// turned at random are wound back as they were (or all the other way, where
// most were turned), each edge-connected part on its own; a consistent mesh is
// left as it is; a second pass turns nothing; and reading a file welds its
// triangles into agreement while the file's own triangles stay for writing.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <string>
#include <utility>

#include "editor/session.h"
#include "io/mesh_file.h"
#include "mesh/builtin_meshes.h"
#include "mesh/orientation.h"
#include "mesh/validation.h"
#include "mesh_fixtures.h"
#include "test_io_support.h"

using namespace vfsd;

namespace {

// Whether u is t with its corners rotated (the same winding).
bool same_winding(const Triangle& t, const Triangle& u) {
    for (int k = 0; k < 3; ++k)
        if (u[0] == t[k] && u[1] == t[(k + 1) % 3] && u[2] == t[(k + 2) % 3]) return true;
    return false;
}

Triangle reversed(const Triangle& t) { return Triangle(t[0], t[2], t[1]); }

std::size_t inconsistent_edges(const std::vector<Triangle>& triangles) {
    TriangleMesh m;
    std::uint32_t n = 0;
    for (const Triangle& t : triangles) n = std::max({n, t[0] + 1, t[1] + 1, t[2] + 1});
    m.positions.assign(n, Vec3(0.0));
    m.triangles = triangles;
    return validate_mesh(m).non_manifold_edges.size();
}

std::vector<TriangleMesh> meshes() {
    return {make_builtin_mesh("sphere", 2), make_builtin_mesh("box", 6), make_builtin_mesh("cylinder", 12),
            make_builtin_mesh("bar", 4),    fixtures::grid(9, 7),        fixtures::annulus(16, 5)};
}

}  // namespace

TEST_CASE("orient_consistently leaves a consistently wound mesh as it is", "[mesh][orientation]") {
    for (const TriangleMesh& m : meshes()) {
        std::vector<Triangle> triangles = m.triangles;
        CHECK(orient_consistently(triangles) == 0);
        CHECK(triangles == m.triangles);
    }
}

TEST_CASE("orient_consistently winds back triangles turned at random", "[mesh][orientation]") {
    std::mt19937 random(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (const TriangleMesh& m : meshes()) {
        for (const double share : {0.02, 0.3, 0.45, 0.7, 0.95}) {
            INFO(m.vertex_count() << " vertices, share turned " << share);
            std::vector<Triangle> triangles = m.triangles;
            std::size_t turned_here = 0;
            for (Triangle& t : triangles)
                if (unit(random) < share) std::swap(t[0], t[1]), ++turned_here;
            // The winding most triangles have is kept; in a tie, the first triangle's.
            const bool first_turned = !same_winding(m.triangles[0], triangles[0]);
            const bool most =
                2 * turned_here > triangles.size() || (2 * turned_here == triangles.size() && first_turned);
            const std::size_t turned = orient_consistently(triangles);
            CHECK(turned == (most ? triangles.size() - turned_here : turned_here));
            for (std::size_t t = 0; t < triangles.size(); ++t)
                REQUIRE(same_winding(most ? reversed(m.triangles[t]) : m.triangles[t], triangles[t]));
            CHECK(inconsistent_edges(triangles) == 0);
            CHECK(orient_consistently(triangles) == 0);
        }
    }
}

TEST_CASE("orient_consistently winds each edge-connected part on its own", "[mesh][orientation]") {
    // Two spheres, and a third touching the first at a vertex only (a pinch):
    // the first mostly turned, the others lightly, each keeps its majority.
    const TriangleMesh sphere = make_builtin_mesh("sphere", 2);
    const auto n = static_cast<std::uint32_t>(sphere.vertex_count());
    std::vector<Triangle> triangles, original;
    for (std::uint32_t part = 0; part < 3; ++part)
        for (const Triangle& t : sphere.triangles) {
            Triangle u = t + Triangle(part * n);
            if (part == 2)  // shares the first sphere's vertex 0 in place of its own
                for (int k = 0; k < 3; ++k)
                    if (u[k] == 2 * n) u[k] = 0;
            original.push_back(u);
        }
    triangles = original;
    std::mt19937 random(9);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (std::size_t t = 0; t < triangles.size(); ++t)
        if (unit(random) < (t < sphere.triangles.size() ? 0.8 : 0.1)) std::swap(triangles[t][1], triangles[t][2]);
    orient_consistently(triangles);
    for (std::size_t t = 0; t < triangles.size(); ++t)
        REQUIRE(same_winding(t < sphere.triangles.size() ? reversed(original[t]) : original[t], triangles[t]));
}

TEST_CASE("orient_consistently ends on a surface that cannot be wound consistently", "[mesh][orientation]") {
    // A Möbius strip of 12 quads: the walk meets itself across one edge.
    std::vector<Triangle> strip;
    const std::uint32_t k = 12;
    for (std::uint32_t i = 0; i < k; ++i) {
        const std::uint32_t a = i, b = i + k, c = (i + 1) % k, d = (i + 1) % k + k;
        // The last quad joins the ends with a half twist: top to bottom.
        const std::uint32_t c2 = i + 1 == k ? d : c, d2 = i + 1 == k ? c : d;
        strip.push_back({a, b, c2});
        strip.push_back({b, d2, c2});
    }
    std::vector<Triangle> wound = strip;
    const std::size_t turned = orient_consistently(wound);
    CHECK(turned <= strip.size() / 2);
    CHECK(inconsistent_edges(wound) >= 1);
    CHECK(orient_consistently(wound) == 0);
}

TEST_CASE("reading a mesh winds its triangles consistently; the file layout keeps the file's",
          "[mesh][orientation][io]") {
    TriangleMesh file = make_builtin_mesh("sphere", 2);
    for (std::size_t t = 0; t < file.triangles.size(); t += 5) std::swap(file.triangles[t][1], file.triangles[t][2]);
    const std::vector<Triangle> as_stored = file.triangles;
    const MeshFile welded = weld_mesh(file, "off");
    CHECK(welded.turned_triangles == (as_stored.size() + 4) / 5);
    CHECK(inconsistent_edges(welded.mesh.triangles) == 0);
    CHECK(welded.file_triangles == as_stored);
    CHECK(to_file_layout(welded, welded.mesh).triangles == as_stored);
    CHECK(turned_triangles_warning(welded).find(std::to_string(welded.turned_triangles) + " of") != std::string::npos);
    CHECK(turned_triangles_warning(weld_mesh(make_builtin_mesh("sphere", 2), "off")).empty());
}

TEST_CASE("a mesh file wound inconsistently opens in the editor with a warning, and deforms",
          "[mesh][orientation][editor]") {
    TriangleMesh file = make_builtin_mesh("cylinder", 8);
    for (std::size_t t = 0; t < file.triangles.size(); t += 3) std::swap(file.triangles[t][1], file.triangles[t][2]);
    vfsd::test::ScratchDir dir;
    write_mesh_file(dir.file("wound.off"), file);
    vfsd::editor::EditorSession session;
    session.open(dir.file("wound.off"));
    const std::vector<std::string> warnings = session.warnings();
    CHECK(std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) {
        return w.find("wound against their neighbours") != std::string::npos;
    }));
    CHECK(inconsistent_edges(session.triangles()) == 0);
    session.set_target_time(1.0);
    session.finish_region();
    while (session.moving()) session.update(1000);
    CHECK(session.folded_triangles().empty());
    CHECK(session.time() == 1.0);
}
