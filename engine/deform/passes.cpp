#include "deform/passes.h"

#include <glm/mat3x3.hpp>

#include "base/parallel.h"
#include "field/vector_field.h"
#include "mesh/geometry.h"

namespace vfsd {
namespace {

// One classical RK4 step of dx/dt = velocity(x, sample) from x.
template <class Velocity>
Vec3 rk4(const StepMotion& m, const Vec3& x, const Velocity& velocity) {
    const double h = m.h;
    const Vec3 k1 = velocity(x, m.start);
    const Vec3 k2 = velocity(x + 0.5 * h * k1, m.middle);
    const Vec3 k3 = velocity(x + 0.5 * h * k2, m.middle);
    const Vec3 k4 = velocity(x + h * k3, m.end);
    return x + (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

}  // namespace

void estimate_normals(const std::vector<Vec3>& positions, const VertexRings& rings, std::vector<Vec3>& normals) {
    vertex_normals(positions, rings, normals);
}

void estimate_normals(const std::vector<Vec3>& positions, const VertexRings& rings,
                      const std::vector<std::uint32_t>& vertices, std::vector<Vec3>& normals) {
    vertex_normals(positions, rings, vertices, normals);
}

std::vector<std::uint32_t> blend_vertices(const std::vector<double>& s) {
    std::vector<std::uint32_t> blend;
    for (std::size_t v = 0; v < s.size(); ++v)
        if (s[v] > 0.0 && s[v] < 1.0) blend.push_back(static_cast<std::uint32_t>(v));
    return blend;
}

void estimate_gradients(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                        const std::vector<double>& s, const VertexRings& rings,
                        const std::vector<std::uint32_t>& blend, std::vector<Vec3>& gradients) {
    gradients.assign(positions.size(), Vec3(0.0));
    parallel_for(blend.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t i = first; i < last; ++i) {
            const std::uint32_t v = blend[i];
            const Vec3 x = positions[v];
            const Vec3 n = normals[v];
            // Normal equations of eq. (6) in the tangent plane: with p = (y − x)
            // projected onto the plane ⊥ n, minimise Σ (g·p − (s(y) − s(x)))². The
            // matrix Σ p pᵀ is singular along n; adding n nᵀ keeps g·n = 0.
            glm::dmat3 normal_matrix(0.0);
            Vec3 rhs(0.0);
            for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
                const std::uint32_t y = rings.neighbours[k];
                const Vec3 d = positions[y] - x;
                const Vec3 p = d - glm::dot(d, n) * n;
                normal_matrix += glm::outerProduct(p, p);
                rhs += (s[y] - s[v]) * p;
            }
            const double scale = normal_matrix[0][0] + normal_matrix[1][1] + normal_matrix[2][2];
            normal_matrix += scale * glm::outerProduct(n, n);
            const double det = glm::determinant(normal_matrix);
            // A ring that spans no plane (fewer than two independent directions) gives no gradient.
            gradients[v] = det > 1e-12 * scale * scale * scale ? glm::inverse(normal_matrix) * rhs : Vec3(0.0);
        }
    });
}

void smooth_gradients(const std::vector<Vec3>& normals, const std::vector<double>& s, const VertexRings& rings,
                      const std::vector<std::uint32_t>& blend, int steps, double weight,
                      std::vector<Vec3>& gradients, std::vector<Vec3>& scratch) {
    // Both buffers hold 0 outside the blend region; the steps write only inside it.
    scratch.assign(gradients.size(), Vec3(0.0));
    for (std::size_t v = 0; v < gradients.size(); ++v)
        if (!(s[v] > 0.0 && s[v] < 1.0)) gradients[v] = Vec3(0.0);
    for (int step = 0; step < steps; ++step) {
        parallel_for(blend.size(), [&](std::size_t first, std::size_t last) {
            for (std::size_t i = first; i < last; ++i) {
                const std::uint32_t v = blend[i];
                // Average over the neighbours inside the blend region only: outside it
                // s is constant, ∇r there carries no information, and mixing it in
                // would shrink ∇r along the region's borders.
                Vec3 sum(0.0);
                int count = 0;
                for (std::uint32_t k = rings.begin(v); k < rings.end(v); ++k) {
                    const std::uint32_t y = rings.neighbours[k];
                    if (s[y] > 0.0 && s[y] < 1.0) sum += gradients[y], ++count;
                }
                const Vec3 g = count > 0 ? gradients[v] + weight * (sum / double(count) - gradients[v]) : gradients[v];
                scratch[v] = g - glm::dot(g, normals[v]) * normals[v];
            }
        });
        gradients.swap(scratch);
    }
}

void predict_midpoints(const MotionSample& start, double h, const std::vector<double>& s,
                       const std::vector<Vec3>& gradients, const std::vector<Vec3>& positions,
                       std::vector<Vec3>& midpoints) {
    midpoints.resize(positions.size());
    parallel_for(positions.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t v = first; v < last; ++v) {
            const Vec3 grad_b = bernstein_blend_derivative(s[v]) * gradients[v];
            midpoints[v] = positions[v] + 0.5 * h * deformation_velocity(start, positions[v], bernstein_blend(s[v]), grad_b);
        }
    });
}

StepMotion StepMotion::sample(const InnerMotion& motion, double t, double h) {
    return {motion.at(t), motion.at(t + 0.5 * h), motion.at(t + h), h};
}

void deformation_step(const StepMotion& motion, const std::vector<double>& s, const std::vector<Vec3>& gradients,
                      std::vector<Vec3>& positions) {
    parallel_for(positions.size(), [&](std::size_t first, std::size_t last) {
        for (std::size_t v = first; v < last; ++v) {
            // r = s and ∇r fixed over the step; ∇b = b'(s) ∇r (eq. 4 with r_i = 0, r_o = 1).
            const double b = bernstein_blend(s[v]);
            if (b == 1.0) continue;  // outer region: v = 0 exactly
            const Vec3 grad_b = bernstein_blend_derivative(s[v]) * gradients[v];
            positions[v] = rk4(motion, positions[v], [&](const Vec3& x, const MotionSample& m) {
                return deformation_velocity(m, x, b, grad_b);
            });
        }
    });
}

void deformation_step(const StepMotion& motion, const SphereTool& tool, std::vector<Vec3>& positions) {
    const double width = tool.r_outer - tool.r_inner;
    for (Vec3& position : positions) {
        position = rk4(motion, position, [&](const Vec3& x, const MotionSample& m) {
            const Vec3 d = x - tool.centre;
            const double r = glm::length(d);
            const double u = (r - tool.r_inner) / width;
            const Vec3 grad_b = r > 0.0 ? bernstein_blend_derivative(u) / width * (d / r) : Vec3(0.0);
            return deformation_velocity(m, x, bernstein_blend(u), grad_b);
        });
    }
}

}  // namespace vfsd
