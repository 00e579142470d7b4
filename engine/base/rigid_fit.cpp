#include "base/rigid_fit.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>

namespace vfsd {
namespace {

using Mat4 = std::array<std::array<double, 4>, 4>;

// Eigenvector of the largest eigenvalue of a symmetric 4×4 matrix (cyclic Jacobi).
std::array<double, 4> dominant_eigenvector(Mat4 a) {
    Mat4 v{};
    for (int i = 0; i < 4; ++i) v[i][i] = 1.0;
    for (int sweep = 0; sweep < 50; ++sweep) {
        double off = 0.0;
        for (int p = 0; p < 4; ++p)
            for (int q = p + 1; q < 4; ++q) off += a[p][q] * a[p][q];
        if (off < 1e-30) break;
        for (int p = 0; p < 4; ++p)
            for (int q = p + 1; q < 4; ++q) {
                if (a[p][q] == 0.0) continue;
                const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 4; ++k) {  // A ← Jᵀ A J, V ← V J
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 4; ++k) {
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 4; ++k) {
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    int best = 0;
    for (int i = 1; i < 4; ++i)
        if (a[i][i] > a[best][best]) best = i;
    return {v[0][best], v[1][best], v[2][best], v[3][best]};
}

glm::dmat3 quaternion_to_matrix(const std::array<double, 4>& q) {
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    glm::dmat3 r;  // column-major: r[col][row]
    r[0] = {1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)};
    r[1] = {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)};
    r[2] = {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)};
    return r;
}

}  // namespace

RigidFit fit_rigid(const std::vector<glm::dvec3>& from, const std::vector<glm::dvec3>& to) {
    RigidFit fit;
    const std::size_t n = std::min(from.size(), to.size());
    if (n == 0) return fit;
    glm::dvec3 cf(0.0), ct(0.0);
    for (std::size_t i = 0; i < n; ++i) cf += from[i], ct += to[i];
    cf /= double(n);
    ct /= double(n);
    double s[3][3] = {};  // cross-covariance Σ a bᵀ
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 a = from[i] - cf, b = to[i] - ct;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) s[r][c] += a[r] * b[c];
    }
    const Mat4 k = {{{s[0][0] + s[1][1] + s[2][2], s[1][2] - s[2][1], s[2][0] - s[0][2], s[0][1] - s[1][0]},
                     {s[1][2] - s[2][1], s[0][0] - s[1][1] - s[2][2], s[0][1] + s[1][0], s[2][0] + s[0][2]},
                     {s[2][0] - s[0][2], s[0][1] + s[1][0], -s[0][0] + s[1][1] - s[2][2], s[1][2] + s[2][1]},
                     {s[0][1] - s[1][0], s[2][0] + s[0][2], s[1][2] + s[2][1], -s[0][0] - s[1][1] + s[2][2]}}};
    fit.rotation = quaternion_to_matrix(dominant_eigenvector(k));
    fit.translation = ct - fit.rotation * cf;
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 d = fit.apply(from[i]) - to[i];
        sum += glm::dot(d, d);
    }
    fit.rms_residual = std::sqrt(sum / double(n));
    return fit;
}

double rotation_angle(const glm::dmat3& r) {
    const double c = 0.5 * (r[0][0] + r[1][1] + r[2][2] - 1.0);
    return std::acos(std::clamp(c, -1.0, 1.0));
}

}  // namespace vfsd
