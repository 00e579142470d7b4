#pragma once
// Painting the region on the surface: label brushes (inner / outer / erase within a
// geodesic radius) and a smooth direct brush on s. Every brush returns its change as a
// RegionEdit, a plain record of old and new values, without touching the state; the
// caller applies it, and an undo stack keeps it to revert. A drag of several dabs is
// one undo step: merge each dab's edit into the stroke's edit.
//
// The labels feed painted_region_field (eq. 16) through label_mask; the direct field s
// is used as is (sec. 3 lets the user define s freely).

#include <cstdint>
#include <vector>

#include "mesh/triangle_mesh.h"
#include "mesh/vertex_rings.h"
#include "region/geodesic.h"
#include "region/surface_point.h"

namespace vfsd {

enum class RegionLabel : std::uint8_t { none = 0, inner = 1, outer = 2 };

struct RegionPaint {
    std::vector<std::uint8_t> labels;  // a RegionLabel per vertex
    std::vector<double> s;             // the directly painted field, one value in [0, 1] per vertex
};

// All labels none, s = 1 (nothing moves).
RegionPaint make_region_paint(std::size_t vertex_count);

// The vertices carrying `label`, as a mask for painted_region_field.
std::vector<std::uint8_t> label_mask(const RegionPaint& paint, RegionLabel label);

enum class RegionChannel { labels, s };

struct RegionEdit {
    RegionChannel channel = RegionChannel::labels;
    std::vector<std::uint32_t> vertices;  // ascending, each once; only vertices that change
    std::vector<double> old_values;       // labels are stored as 0, 1, 2 (exact)
    std::vector<double> new_values;
};

// Set the edit's new (apply) or old (revert) values. Throw InputError when the edit's
// arrays differ in length or a vertex is out of range for `paint`.
void apply_edit(RegionPaint& paint, const RegionEdit& edit);
void revert_edit(RegionPaint& paint, const RegionEdit& edit);

// Folds `dab`, computed after `stroke` was applied, into `stroke`: vertices in both
// keep the stroke's old value and take the dab's new value. Reverting the merged edit
// undoes both. Throws InputError when the channels differ.
void merge_edit(RegionEdit& stroke, const RegionEdit& dab);

enum class LabelBrush { paint_inner, paint_outer, erase };

// Sets (or clears, for erase) the label of every vertex within geodesic distance
// `radius` of `centre`. Throws InputError for a radius that is not positive and finite,
// or a paint state whose size differs from the vertex count.
RegionEdit label_brush(const RegionPaint& paint, const std::vector<Vec3>& positions,
                       const std::vector<Triangle>& triangles, const VertexRings& rings, const SurfacePoint& centre,
                       double radius, LabelBrush mode, const GeodesicOptions& options = {});

// Moves s towards `target` with a smooth falloff of the geodesic distance g:
//   s <- s + strength * w(g / radius) * (target - s),  w(x) = (1 - x^2)^2 for x < 1, else 0
// (w is 1 at the centre and meets 0 with zero slope at the rim). target and strength
// must lie in [0, 1], so s stays in [0, 1].
RegionEdit field_brush(const RegionPaint& paint, const std::vector<Vec3>& positions,
                       const std::vector<Triangle>& triangles, const VertexRings& rings, const SurfacePoint& centre,
                       double radius, double target, double strength, const GeodesicOptions& options = {});

}  // namespace vfsd
