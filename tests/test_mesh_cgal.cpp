// Validation and volume on a real scanned mesh: CGAL's armadillo.off
// (scripts/get-cgal-meshes fetches it; the test is skipped without it).

#include <catch2/catch.hpp>

#include <filesystem>

#include "io/mesh_file.h"
#include "mesh/geometry.h"
#include "mesh/validation.h"

using namespace vfsd;

namespace {

// Volume by the divergence theorem, V = 1/3 sum_t area_t (centroid_t - c) . n_t,
// about the vertex centroid c: another origin and another grouping of terms than
// signed_volume()'s tetrahedra at the origin.
double divergence_volume(const TriangleMesh& mesh) {
    Vec3 c(0.0);
    for (const Vec3& p : mesh.positions) c += p;
    c /= double(mesh.vertex_count());
    double sum = 0.0;
    for (const Triangle& t : mesh.triangles) {
        const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], d = mesh.positions[t[2]];
        const Vec3 area_normal = 0.5 * glm::cross(b - a, d - a);
        sum += glm::dot((a + b + d) / 3.0 - c, area_normal);
    }
    return sum / 3.0;
}

}  // namespace

TEST_CASE("CGAL's armadillo is closed and manifold, and its volume agrees two ways", "[mesh][cgal]") {
    const std::filesystem::path path = std::filesystem::path(VFSD_SOURCE_DIR) / "assets/cgal/armadillo.off";
    if (!std::filesystem::exists(path)) {
        WARN("skipped: " << path.string() << " is absent (run scripts/get-cgal-meshes)");
        return;
    }
    const TriangleMesh mesh = read_mesh_file(path.string()).mesh;
    CHECK(mesh.vertex_count() == 26002);
    CHECK(mesh.triangle_count() == 52000);
    const ValidationReport r = validate_mesh(mesh);
    CHECK(r.is_closed);
    CHECK(r.is_manifold);
    CHECK(r.reasons.empty());
    CHECK(r.isolated_vertices.empty());
    CHECK(r.boundary_loops.empty());
    const double volume = signed_volume(mesh.positions, mesh.triangles);
    CHECK(volume > 0.0);
    CHECK(volume == Approx(divergence_volume(mesh)).epsilon(1e-9));
}
