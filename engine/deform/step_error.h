#pragma once
// The error estimate of one step (beyond the paper; docs/method.md,
// "Error-controlled steps"), shared by the CPU's and the GPU's steps: at sample
// vertices of the blend region, the field at the step's middle with the ∇r the
// step takes against the ∇r its midpoints were predicted with.

#include <algorithm>
#include <cstddef>

#include <glm/geometric.hpp>

#include "curve/inner_motion.h"
#include "field/vector_field.h"

namespace vfsd {

struct StepErrorSample {
    Vec3 midpoint{0.0};
    double s = 0.0;
    Vec3 predicted_gradient{0.0};  // ∇r the midpoints were predicted with
    Vec3 gradient{0.0};            // ∇r at the midpoints, which the step takes
};

// max over the samples of |v(∇r) − v(predicted ∇r)| · h² / span, where `span` is
// the time between the two ∇r: the difference a step of length h would see
// between ∇r taken at its start and at its middle, in position units. 0 with no
// samples or no time between the two.
template <class Sample>
double sampled_step_error(const MotionSample& middle, double h, double span, std::size_t count, const Sample& sample) {
    if (!(span > 1e-12)) return 0.0;
    double largest = 0.0;
    for (std::size_t j = 0; j < count; ++j) {
        const StepErrorSample e = sample(j);
        const double b = bernstein_blend(e.s), db = bernstein_blend_derivative(e.s);
        const Vec3 dv = deformation_velocity(middle, e.midpoint, b, db * e.gradient) -
                        deformation_velocity(middle, e.midpoint, b, db * e.predicted_gradient);
        largest = std::max(largest, glm::length(dv));
    }
    return largest * h * h / span;
}

}  // namespace vfsd
