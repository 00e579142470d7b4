#pragma once
// A scene and its mesh placed elsewhere: turned, moved, scaled uniformly or
// mirrored. The method has no preferred place, orientation, size or handedness
// (eqs. 1–14 are built from c(t), its derivatives and s, all of which move with
// the scene), so a placed scene must deform into the placed result. The tests
// hold the engine to that, and `vfsd battery` places its scenes at random.

#include <glm/mat3x3.hpp>

#include "scene/scene.h"

namespace vfsd {

// x ↦ scale · rotation · x + offset, with `rotation` orthogonal: det +1 turns,
// det −1 mirrors.
struct Placement {
    glm::dmat3 rotation{1.0};
    double scale = 1.0;
    Vec3 offset{0.0};

    Vec3 point(const Vec3& x) const { return scale * (rotation * x) + offset; }
    Vec3 direction(const Vec3& d) const { return rotation * d; }
    bool mirrors() const;
};

// Every point, length and direction of the scene placed. A mirror image turns
// every twist the other way (a right-handed twist seen in a mirror is a
// left-handed one), so the twist angles are negated. Throws InputError for a
// box selector under a rotation that does not keep boxes axis-aligned.
Scene place_scene(const Scene& scene, const Placement& placement);

// The mesh's positions placed; a mirror also reverses every triangle's winding,
// so that triangles keep facing outward.
void place_mesh(TriangleMesh& mesh, const Placement& placement);

}  // namespace vfsd
