#include "scene/framing.h"

#include <algorithm>

namespace vfsd {

std::vector<Vec3> deformation_frame_points(const std::vector<Vec3>& positions, const std::vector<double>& s,
                                          const InnerMotion& motion) {
    std::vector<Vec3> points = positions;
    if (motion.is_fixed_rotation()) return points;
    const Vec3 start = motion.curve().at(0.0).position;
    double reach = 0.0;
    for (std::size_t v = 0; v < positions.size() && v < s.size(); ++v)
        if (s[v] <= 0.0) reach = std::max(reach, glm::length(positions[v] - start));
    for (int i = 0; i <= 32; ++i) {
        const Vec3 c = motion.curve().at(i / 32.0).position;
        points.push_back(c);
        for (int axis = 0; axis < 3; ++axis) {
            Vec3 d(0.0);
            d[axis] = reach;
            points.push_back(c + d);
            points.push_back(c - d);
        }
    }
    return points;
}

}  // namespace vfsd
