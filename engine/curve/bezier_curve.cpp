#include "curve/bezier_curve.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "base/error.h"

namespace vfsd {

BezierCurve::BezierCurve(std::vector<Vec3> control_points) : points_(std::move(control_points)) {
    const std::size_t n = points_.size();
    if (n < 4 || (n - 1) % 3 != 0)
        throw InputError("curve: a composite cubic Bézier needs 3k+1 control points (k >= 1), got " + std::to_string(n));
    for (const Vec3& p : points_)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw InputError("curve: control points must be finite");
}

CurvePoint BezierCurve::at(double t, JoinSide side) const {
    // Map t to segment j and local parameter u; d/dt = k d/du.
    const double k = static_cast<double>(segment_count());
    const double tk = std::clamp(t, 0.0, 1.0) * k;
    const double join = std::round(tk);
    const bool on_join = std::abs(tk - join) < 1e-9 * k;
    std::size_t j = std::min(static_cast<std::size_t>(on_join ? join : tk), segment_count() - 1);
    if (on_join && side == JoinSide::before && join >= 1.0) j = static_cast<std::size_t>(join) - 1;
    const double u = on_join ? join - static_cast<double>(j) : tk - static_cast<double>(j);
    const Vec3& b0 = points_[3 * j];
    const Vec3& b1 = points_[3 * j + 1];
    const Vec3& b2 = points_[3 * j + 2];
    const Vec3& b3 = points_[3 * j + 3];
    const double v = 1.0 - u;
    CurvePoint c;
    c.position = v * v * v * b0 + 3.0 * v * v * u * b1 + 3.0 * v * u * u * b2 + u * u * u * b3;
    c.d1 = 3.0 * k * (v * v * (b1 - b0) + 2.0 * v * u * (b2 - b1) + u * u * (b3 - b2));
    c.d2 = 6.0 * k * k * (v * (b2 - 2.0 * b1 + b0) + u * (b3 - 2.0 * b2 + b1));
    c.d3 = 6.0 * k * k * k * (b3 - 3.0 * b2 + 3.0 * b1 - b0);
    return c;
}

double BezierCurve::polygon_length() const {
    double length = 0.0;
    for (std::size_t i = 1; i < points_.size(); ++i) length += glm::length(points_[i] - points_[i - 1]);
    return length;
}

}  // namespace vfsd
