#pragma once
// A scene that folds: fig. 5's box twisted by 180° with sec. 5 as printed (no
// stream gauge fit, no volume keeper, no fold repair, tangent smoothing) and no
// smoothing steps.
// The fold guard's tests need folds to report and draw.

#include <string>

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

}  // namespace vfsd::test
