#pragma once
// How a scene's inner region moves: the curve (or handle) and the motion settings
// around it, as a scene file states them (the keys "curve", "inner_motion",
// "twist_degrees", "twist_plane" and "stream_origin" of scene/scene.h). The
// editors edit this same value (editor/session.h: curve()).

#include <optional>
#include <vector>

#include "curve/handle.h"

namespace vfsd {

struct CurveSpec {
    bool is_handle = false;
    std::vector<Vec3> bezier;  // 3k+1 control points
    HandleFrame from, to;      // handle mode (sec. 6.2)
};

struct MotionSpec {
    CurveSpec curve;
    InnerMotionMode inner_motion = InnerMotionMode::Rotation;
    double twist_degrees[2] = {0.0, 0.0};  // α(0), α(1) of eq. (14)
    // Plane ẽ = 0 of the twist at this signed distance along ĉ from c; unset means
    // "region": at the far end of the moving part (see InnerMotion::set_twist_plane).
    std::optional<double> twist_plane;
    // A fixed point the stream of eqs. (9)–(13) is built about; unset means "curve":
    // c(t), as eq. (10) (see InnerMotion::set_stream_origin).
    std::optional<Vec3> stream_origin;
};

bool operator==(const CurveSpec& a, const CurveSpec& b);
bool operator==(const MotionSpec& a, const MotionSpec& b);
inline bool operator!=(const MotionSpec& a, const MotionSpec& b) { return !(a == b); }

// The inner motion the curve (or handle), mode and twist describe; throws
// InputError when they describe none. An unset twist plane keeps the motion's
// default: prepare_scene, which knows the region, places it.
InnerMotion build_motion(const MotionSpec& spec);

}  // namespace vfsd
