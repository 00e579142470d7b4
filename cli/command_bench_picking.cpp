// vfsd bench --picking [--mesh SPEC] [--rays N]
//
// What the editors pay to find the surface under the pointer on a large mesh:
// building the bounding volume hierarchy (once per mesh), refitting it (after
// the deformation moved the vertices), one pick through it, and one pick by the
// loop over all triangles it replaces. Every pick through the hierarchy is checked
// against the loop on a sample of the rays. The refit runs on parallel_for's
// threads, the rest on one.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "base/error.h"
#include "base/parallel.h"
#include "cli/commands.h"
#include "io/mesh_file.h"
#include "mesh/geometry.h"
#include "mesh/ray_cast.h"
#include "mesh/triangle_bvh.h"

namespace vfsd::cli {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Rays as a pointer over the view makes them: from a sphere around the mesh
// toward random points of its bounding box.
std::vector<Ray> pointer_rays(const std::vector<Vec3>& positions, int count) {
    std::mt19937 random(1);
    std::normal_distribution<double> normal;
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const BoundingBox box = bounding_box(positions);
    std::vector<Ray> rays;
    for (int i = 0; i < count; ++i) {
        const Vec3 eye = box.centre() + 1.5 * box.diagonal() * glm::normalize(Vec3(normal(random), normal(random), normal(random)));
        const Vec3 at = box.min + Vec3(unit(random), unit(random), unit(random)) * box.extent();
        rays.push_back({eye, glm::normalize(at - eye)});
    }
    return rays;
}

// Every vertex moved a little, as a deformation step would.
std::vector<Vec3> moved(std::vector<Vec3> positions, double by) {
    for (std::size_t v = 0; v < positions.size(); ++v) positions[v] += by * Vec3(std::sin(v * 0.1), std::cos(v * 0.1), 0.0);
    return positions;
}

bool same(const std::optional<RayHit>& a, const std::optional<RayHit>& b) {
    if (!a || !b) return a.has_value() == b.has_value();
    return a->triangle == b->triangle && a->u == b->u && a->v == b->v && a->t == b->t;
}

}  // namespace

int run_picking_bench(const Args& args) {
    args.expect({"picking", "mesh", "rays"}, 0, 0);
    const std::string spec = args.get("mesh", "builtin:cylinder:707");
    const int count = static_cast<int>(args.get_number("rays", 1000));
    if (count < 1) throw UsageError("--rays must be positive");
    const TriangleMesh mesh = load_mesh(spec);
    std::printf("picking on %s: %zu vertices, %zu triangles, %d rays\n", spec.c_str(), mesh.vertex_count(),
                mesh.triangle_count(), count);

    auto start = Clock::now();
    TriangleBvh bvh(mesh.positions, mesh.triangles);
    std::printf("  BVH build               %9.1f ms   (%zu nodes, depth %zu)\n", ms_since(start), bvh.node_count(), bvh.depth());

    const std::vector<Vec3> deformed = moved(mesh.positions, 1e-3 * bounding_box(mesh.positions).diagonal());
    std::vector<double> refit_ms;
    for (int k = 0; k < 5; ++k) {
        start = Clock::now();
        bvh.refit(k % 2 ? mesh.positions : deformed);
        refit_ms.push_back(ms_since(start));
    }
    std::printf("  BVH refit               %9.1f ms   (median of 5, %u threads)\n", median(refit_ms),
                parallel_thread_count());
    bvh.refit(mesh.positions);

    const std::vector<Ray> rays = pointer_rays(mesh.positions, count);
    std::vector<double> bvh_us;
    std::vector<std::optional<RayHit>> hits;
    for (const Ray& ray : rays) {
        start = Clock::now();
        hits.push_back(bvh.first_hit(ray, mesh.positions));
        bvh_us.push_back(1e3 * ms_since(start));
    }
    std::size_t hit_count = 0;
    for (const auto& h : hits) hit_count += h.has_value();
    std::printf("  pick through the BVH    %9.2f us   (median; %zu of %d rays hit)\n", median(bvh_us), hit_count, count);

    // The loop is slow: a sample of the rays, each checked against the hierarchy's hit.
    std::vector<double> loop_ms;
    std::size_t disagree = 0;
    for (std::size_t i = 0; i < rays.size(); i += std::max<std::size_t>(1, rays.size() / 20)) {
        start = Clock::now();
        const auto hit = first_hit_brute_force(rays[i], mesh.positions, mesh.triangles);
        loop_ms.push_back(ms_since(start));
        disagree += !same(hit, hits[i]);
    }
    std::printf("  pick, every triangle    %9.2f ms   (median of %zu rays; %zu disagree with the BVH)\n", median(loop_ms),
                loop_ms.size(), disagree);
    return disagree == 0 ? kExitOk : kExitInput;
}

}  // namespace vfsd::cli
