#pragma once
// The coordinates a deformation integrates in: centred on the mesh's bounding
// box and scaled by a power of two to a diagonal between 1 and 2, so that the
// same shape 1e9 units from the origin, or 1e-30 units across, deforms as the
// unit one does (the field's terms grow like |x − c|² and |x − c|³, and far from
// the origin a step's displacement would be lost in the rounding of x).
// Scaling by a power of two is exact both ways; the centre's subtraction
// rounds each coordinate once, to the last bit of the larger of |x| and |centre|.

#include <vector>

#include "curve/inner_motion.h"

namespace vfsd {

struct LocalFrame {
    // Beyond this the field's cubic terms overflow even in the local frame's
    // arithmetic on the way there (squared distances of the region field).
    static constexpr double kLargestDiagonal = 1e150;

    Vec3 centre{0.0};
    double scale = 1.0;  // a power of two

    // The frame of the finite ones among `positions` (a non-finite position is
    // left to the integration's check, which names the vertex); the identity for
    // none. Throws InputError "coordinates too large" beyond kLargestDiagonal.
    static LocalFrame of(const std::vector<Vec3>& positions);

    Vec3 to_local(const Vec3& x) const { return (x - centre) * scale; }
    Vec3 to_world(const Vec3& x) const { return x / scale + centre; }
    // The motion in local coordinates: points moved and scaled, velocities scaled,
    // angular velocities (rates) as they are.
    MotionSample to_local(const MotionSample& m) const;
};

}  // namespace vfsd
