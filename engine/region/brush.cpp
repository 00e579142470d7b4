#include "region/brush.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "base/error.h"

namespace vfsd {
namespace {

void check_paint(const RegionPaint& paint, std::size_t n) {
    if (paint.labels.size() != n || paint.s.size() != n)
        throw InputError("region paint: the state has " + std::to_string(paint.labels.size()) + " labels and " +
                         std::to_string(paint.s.size()) + " values of s for " + std::to_string(n) + " vertices");
}

// Geodesic distances from the brush centre, propagated no farther than the radius.
std::vector<double> brush_distances(const RegionPaint& paint, const std::vector<Vec3>& positions,
                                    const std::vector<Triangle>& triangles, const VertexRings& rings,
                                    const SurfacePoint& centre, double radius, GeodesicOptions options) {
    check_paint(paint, positions.size());
    if (!(radius > 0.0) || !std::isfinite(radius)) throw InputError("brush: the radius must be positive and finite");
    options.max_distance = radius;
    return geodesic_distance_from_point(positions, triangles, rings, centre, options);
}

void record(RegionEdit& edit, std::uint32_t v, double old_value, double new_value) {
    if (old_value == new_value) return;
    edit.vertices.push_back(v);
    edit.old_values.push_back(old_value);
    edit.new_values.push_back(new_value);
}

void set_values(RegionPaint& paint, const RegionEdit& edit, const std::vector<double>& values) {
    if (edit.old_values.size() != edit.vertices.size() || edit.new_values.size() != edit.vertices.size())
        throw InputError("region edit: vertex and value arrays differ in length");
    for (std::size_t i = 0; i < edit.vertices.size(); ++i) {
        const std::uint32_t v = edit.vertices[i];
        if (v >= paint.labels.size() || v >= paint.s.size())
            throw InputError("region edit: vertex " + std::to_string(v) + " out of range");
        if (edit.channel == RegionChannel::s) {
            paint.s[v] = values[i];
            continue;
        }
        if (values[i] != 0.0 && values[i] != 1.0 && values[i] != 2.0)
            throw InputError("region edit: a label value must be 0 (none), 1 (inner) or 2 (outer)");
        paint.labels[v] = static_cast<std::uint8_t>(values[i]);
    }
}

}  // namespace

RegionPaint make_region_paint(std::size_t vertex_count) {
    return {std::vector<std::uint8_t>(vertex_count, static_cast<std::uint8_t>(RegionLabel::none)),
            std::vector<double>(vertex_count, 1.0)};
}

std::vector<std::uint8_t> label_mask(const RegionPaint& paint, RegionLabel label) {
    std::vector<std::uint8_t> mask(paint.labels.size());
    for (std::size_t v = 0; v < mask.size(); ++v) mask[v] = paint.labels[v] == static_cast<std::uint8_t>(label);
    return mask;
}

void apply_edit(RegionPaint& paint, const RegionEdit& edit) { set_values(paint, edit, edit.new_values); }

void revert_edit(RegionPaint& paint, const RegionEdit& edit) { set_values(paint, edit, edit.old_values); }

void merge_edit(RegionEdit& stroke, const RegionEdit& dab) {
    if (stroke.channel != dab.channel) throw InputError("region edit: cannot merge edits of different channels");
    // Both vertex lists are ascending: merge them like sorted runs.
    RegionEdit out{stroke.channel, {}, {}, {}};
    std::size_t i = 0, j = 0;
    while (i < stroke.vertices.size() || j < dab.vertices.size()) {
        const bool take_stroke = j == dab.vertices.size() ||
                                 (i < stroke.vertices.size() && stroke.vertices[i] < dab.vertices[j]);
        const bool both = i < stroke.vertices.size() && j < dab.vertices.size() && stroke.vertices[i] == dab.vertices[j];
        if (both) {
            out.vertices.push_back(stroke.vertices[i]);
            out.old_values.push_back(stroke.old_values[i++]);
            out.new_values.push_back(dab.new_values[j++]);
        } else if (take_stroke) {
            out.vertices.push_back(stroke.vertices[i]);
            out.old_values.push_back(stroke.old_values[i]);
            out.new_values.push_back(stroke.new_values[i++]);
        } else {
            out.vertices.push_back(dab.vertices[j]);
            out.old_values.push_back(dab.old_values[j]);
            out.new_values.push_back(dab.new_values[j++]);
        }
    }
    stroke = std::move(out);
}

RegionEdit label_brush(const RegionPaint& paint, const std::vector<Vec3>& positions,
                       const std::vector<Triangle>& triangles, const VertexRings& rings, const SurfacePoint& centre,
                       double radius, LabelBrush mode, const GeodesicOptions& options) {
    const std::vector<double> g = brush_distances(paint, positions, triangles, rings, centre, radius, options);
    const RegionLabel label = mode == LabelBrush::paint_inner   ? RegionLabel::inner
                              : mode == LabelBrush::paint_outer ? RegionLabel::outer
                                                                : RegionLabel::none;
    RegionEdit edit{RegionChannel::labels, {}, {}, {}};
    for (std::uint32_t v = 0; v < g.size(); ++v)
        if (g[v] <= radius) record(edit, v, paint.labels[v], static_cast<double>(label));
    return edit;
}

RegionEdit field_brush(const RegionPaint& paint, const std::vector<Vec3>& positions,
                       const std::vector<Triangle>& triangles, const VertexRings& rings, const SurfacePoint& centre,
                       double radius, double target, double strength, const GeodesicOptions& options) {
    if (!(target >= 0.0 && target <= 1.0) || !(strength >= 0.0 && strength <= 1.0))
        throw InputError("field brush: target and strength must lie in [0, 1]");
    const std::vector<double> g = brush_distances(paint, positions, triangles, rings, centre, radius, options);
    RegionEdit edit{RegionChannel::s, {}, {}, {}};
    for (std::uint32_t v = 0; v < g.size(); ++v) {
        if (!(g[v] < radius)) continue;
        const double x = g[v] / radius;
        const double w = (1.0 - x * x) * (1.0 - x * x);  // smooth falloff, 1 at the centre, 0 at the rim
        const double s = paint.s[v] + strength * w * (target - paint.s[v]);
        record(edit, v, paint.s[v], std::clamp(s, 0.0, 1.0));
    }
    return edit;
}

}  // namespace vfsd
