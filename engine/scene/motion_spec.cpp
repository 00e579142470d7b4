#include "scene/motion_spec.h"

namespace vfsd {
namespace {

constexpr double kDegrees = 3.14159265358979323846 / 180.0;

bool same_frame(const HandleFrame& a, const HandleFrame& b) {
    return a.position == b.position && a.normal == b.normal && a.binormal == b.binormal;
}

}  // namespace

bool operator==(const CurveSpec& a, const CurveSpec& b) {
    return a.is_handle == b.is_handle && a.bezier == b.bezier && same_frame(a.from, b.from) && same_frame(a.to, b.to);
}

bool operator==(const MotionSpec& a, const MotionSpec& b) {
    return a.curve == b.curve && a.inner_motion == b.inner_motion && a.twist_degrees[0] == b.twist_degrees[0] &&
           a.twist_degrees[1] == b.twist_degrees[1] && a.twist_plane == b.twist_plane &&
           a.stream_origin == b.stream_origin;
}

InnerMotion build_motion(const MotionSpec& spec) {
    const CurveSpec& c = spec.curve;
    InnerMotion motion = c.is_handle ? handle_motion(c.from, c.to)
                                     : InnerMotion::along_curve(BezierCurve(c.bezier), spec.inner_motion,
                                                                spec.twist_degrees[0] * kDegrees,
                                                                spec.twist_degrees[1] * kDegrees);
    if (spec.twist_plane) motion.set_twist_plane(*spec.twist_plane);
    motion.set_stream_origin(spec.stream_origin);
    return motion;
}

}  // namespace vfsd
