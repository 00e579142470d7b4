#pragma once
// A scene that folds: fig. 5's box twisted by 180° with sec. 5 as printed (no
// stream gauge fit, no volume keeper, no fold repair, tangent smoothing) and no
// smoothing steps.
// The fold guard's tests need folds to report and draw. And a rough sphere, for
// the fold tests that must not count a scanned surface's bumps.

#include <random>
#include <string>

#include "mesh/builtin_meshes.h"
#include "scene/scene.h"

namespace vfsd::test {

inline Scene folding_box_scene() {
    Scene scene = load_scene(std::string(VFSD_SOURCE_DIR) + "/assets/scenes/fig05-box-bend-twist.json");
    scene.motion.twist_degrees[1] = 180.0;
    scene.options.fit_stream_gauge = scene.options.keep_volume = scene.options.repair_folds = false;
    scene.options.tangent_smoothing = true;
    scene.options.smoothing_steps = 0;
    scene.options.steps = 40;
    scene.region.profile = RegionSpec::Profile::geodesic;  // eq. (16) as printed too
    return scene;
}

// A unit sphere whose vertices are moved radially by up to ±`roughness` (its
// edges are about 0.13 long): a scanned surface's bumps at the scale of one triangle.
inline TriangleMesh rough_sphere(double roughness, std::mt19937& random) {
    TriangleMesh m = make_builtin_mesh("sphere", 3);
    std::uniform_real_distribution<double> bump(-roughness, roughness);
    for (Vec3& p : m.positions) p *= 1.0 + bump(random);
    return m;
}

}  // namespace vfsd::test
