#include "scene/scene_transform.h"

#include <cmath>
#include <utility>

#include <glm/matrix.hpp>

#include "base/error.h"

namespace vfsd {
namespace {

// A box stays a box only under a rotation that permutes and flips the axes.
bool keeps_axes(const glm::dmat3& r) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (std::abs(r[i][j]) > 1e-12 && std::abs(std::abs(r[i][j]) - 1.0) > 1e-12) return false;
    return true;
}

Selector place_selector(Selector s, const Placement& p) {
    switch (s.kind) {
        case SelectorKind::sphere:
            s.a = p.point(s.a);
            s.value *= p.scale;
            break;
        case SelectorKind::halfspace: {
            // n·x ≥ d at x is (R n)·x′ ≥ scale d + (R n)·offset at x′ = scale R x + offset.
            const Vec3 n = p.direction(s.a);
            s.value = p.scale * s.value + glm::dot(n, p.offset);
            s.a = n;
            break;
        }
        case SelectorKind::box: {
            if (!keeps_axes(p.rotation)) throw InputError("a box selector cannot be turned off the axes");
            const Vec3 a = p.point(s.a), b = p.point(s.b);
            s.a = glm::min(a, b);
            s.b = glm::max(a, b);
            break;
        }
        case SelectorKind::vertices: break;
    }
    return s;
}

void place_selectors(std::vector<Selector>& selectors, const Placement& p) {
    for (Selector& s : selectors) s = place_selector(std::move(s), p);
}

HandleFrame place_frame(HandleFrame f, const Placement& p) {
    f.position = p.point(f.position);
    f.normal = p.direction(f.normal);
    f.binormal = p.direction(f.binormal);
    return f;
}

}  // namespace

bool Placement::mirrors() const { return glm::determinant(rotation) < 0.0; }

Scene place_scene(const Scene& scene, const Placement& p) {
    Scene out = scene;
    RegionSpec& r = out.region;
    place_selectors(r.inner, p);
    place_selectors(r.outer, p);
    r.seed = p.point(r.seed);
    r.band *= p.scale;
    r.g_min *= p.scale;
    r.g_max *= p.scale;
    r.geodesic.max_distance *= p.scale;
    r.sphere.centre = p.point(r.sphere.centre);
    r.sphere.r_inner *= p.scale;
    r.sphere.r_outer *= p.scale;
    MotionSpec& m = out.motion;
    for (Vec3& b : m.curve.bezier) b = p.point(b);
    m.curve.from = place_frame(m.curve.from, p);
    m.curve.to = place_frame(m.curve.to, p);
    if (p.mirrors()) m.twist_degrees[0] = -m.twist_degrees[0], m.twist_degrees[1] = -m.twist_degrees[1];
    if (m.twist_plane) *m.twist_plane *= p.scale;  // a signed distance along ĉ, which turns with the scene
    if (m.stream_origin) m.stream_origin = p.point(*m.stream_origin);
    return out;
}

void place_mesh(TriangleMesh& mesh, const Placement& p) {
    for (Vec3& x : mesh.positions) x = p.point(x);
    if (p.mirrors())
        for (Triangle& t : mesh.triangles) std::swap(t.y, t.z);
}

}  // namespace vfsd
