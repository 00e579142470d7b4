#include "curve/curve_on_region.h"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

namespace vfsd {

glm::dmat3 turn_onto(const Vec3& a, const Vec3& b) {
    const double c = glm::dot(a, b);
    if (c < -1.0 + 1e-12) {
        const Vec3 other = std::abs(a.x) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
        const Vec3 axis = glm::normalize(glm::cross(a, other));
        return glm::dmat3(2.0 * glm::outerProduct(axis, axis)) - glm::dmat3(1.0);
    }
    // Rodrigues: R = I + [k]× + [k]×² / (1 + c), k = a × b.
    const Vec3 k = glm::cross(a, b);
    const glm::dmat3 cross(0.0, k.z, -k.y, -k.z, 0.0, k.x, k.y, -k.x, 0.0);  // columns of [k]×
    return glm::dmat3(1.0) + cross + (cross * cross) / (1.0 + c);
}

Vec3 inner_region_axis(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                       const std::vector<double>& s) {
    Vec3 inner(0.0), blend(0.0), normal(0.0);
    std::size_t n_inner = 0, n_blend = 0;
    double size = 0.0;
    for (std::size_t v = 0; v < positions.size(); ++v) {
        if (s[v] <= 0.0) inner += positions[v], normal += normals[v], ++n_inner;
        else if (s[v] < 1.0) blend += positions[v], ++n_blend;
    }
    if (n_inner == 0) return Vec3(0.0);
    inner /= double(n_inner);
    for (std::size_t v = 0; v < positions.size(); ++v)
        if (s[v] <= 0.0) size = std::max(size, glm::length(positions[v] - inner));
    // Out through the inner region from the blend region's centroid, unless that is
    // hardly apart from the inner centroid (a blend ring all round it).
    if (n_blend > 0) {
        const Vec3 away = inner - blend / double(n_blend);
        if (glm::length(away) > 0.25 * size && glm::length(away) > 0.0) return glm::normalize(away);
    }
    return glm::length(normal) > 0.0 ? glm::normalize(normal) : Vec3(0.0);
}

std::vector<Vec3> curve_on_region(const std::vector<Vec3>& control_points, const std::vector<Vec3>& positions,
                                  const std::vector<Vec3>& normals, const std::vector<double>& s) {
    Vec3 centroid(0.0);
    std::size_t count = 0;
    for (std::size_t v = 0; v < positions.size(); ++v)
        if (s[v] <= 0.0) centroid += positions[v], ++count;
    if (count == 0 || control_points.empty()) return control_points;
    centroid /= double(count);
    const Vec3 start = control_points.front();
    glm::dmat3 turn(1.0);
    const Vec3 axis = inner_region_axis(positions, normals, s);
    for (const Vec3& p : control_points) {
        const Vec3 d = p - start;
        if (glm::length(d) > 0.0) {
            if (glm::length(axis) > 0.0) turn = turn_onto(glm::normalize(d), axis);
            break;
        }
    }
    std::vector<Vec3> placed;
    placed.reserve(control_points.size());
    for (const Vec3& p : control_points) placed.push_back(centroid + turn * (p - start));
    return placed;
}

}  // namespace vfsd
