#pragma once
// A composite cubic Bézier curve c(t), t in [0,1]: 3k+1 control points make k
// segments joined end to end (so a knot as in fig. 14 is one curve). Segment j
// covers t in [j/k, (j+1)/k]; derivatives are exact and taken with respect to t.

#include <vector>

#include "mesh/triangle_mesh.h"

namespace vfsd {

struct CurvePoint {
    Vec3 position;  // c(t)
    Vec3 d1;        // c'(t)
    Vec3 d2;        // c''(t)
    Vec3 d3;        // c'''(t), constant on each segment
};

// Which segment a join belongs to: derivatives may jump there, and a step that
// ends on a join takes the segment it comes from.
enum class JoinSide { after, before };

class BezierCurve {
public:
    BezierCurve() = default;
    // Throws InputError unless there are 3k+1 (k >= 1) finite control points.
    explicit BezierCurve(std::vector<Vec3> control_points);

    // At a join (t within 1e-9 of j / k) the segment after it, or with
    // JoinSide::before the one before it.
    CurvePoint at(double t, JoinSide side = JoinSide::after) const;
    std::size_t segment_count() const { return (points_.size() - 1) / 3; }
    const std::vector<Vec3>& control_points() const { return points_; }
    // Upper bound of the curve's length (control polygon length); 0 for a point.
    double polygon_length() const;

private:
    std::vector<Vec3> points_;
};

}  // namespace vfsd
