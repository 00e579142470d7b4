#include "deform/local_frame.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "base/error.h"

namespace vfsd {

LocalFrame LocalFrame::of(const std::vector<Vec3>& positions) {
    LocalFrame frame;
    Vec3 lo(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Vec3& p : positions)
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) lo = glm::min(lo, p), hi = glm::max(hi, p);
    if (!(lo.x <= hi.x)) return frame;  // no finite position (the integration names the vertex)
    const Vec3 extent = hi - lo;
    // hypot, so that the diagonal of a box 1e200 across is still a number.
    const double diagonal = std::hypot(std::hypot(extent.x, extent.y), extent.z);
    if (!std::isfinite(diagonal) || diagonal > kLargestDiagonal) {
        char message[160];
        std::snprintf(message, sizeof message,
                      "coordinates too large: the mesh is %.3g units across, vfsd deforms meshes up to %g across",
                      diagonal, kLargestDiagonal);
        throw InputError(message);
    }
    frame.centre = 0.5 * lo + 0.5 * hi;
    if (diagonal > 0.0) frame.scale = std::ldexp(1.0, -std::ilogb(diagonal));  // diagonal · scale in [1, 2)
    return frame;
}

MotionSample LocalFrame::to_local(const MotionSample& m) const {
    MotionSample local = m;
    local.position = to_local(m.position);
    local.velocity = m.velocity * scale;
    local.twist_origin = to_local(m.twist_origin);
    local.stream_origin = to_local(m.stream_origin);
    return local;
}

}  // namespace vfsd
