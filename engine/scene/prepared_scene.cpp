#include "scene/prepared_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "base/error.h"
#include "deform/local_frame.h"
#include "field/vector_field.h"
#include "region/harmonic_blend.h"
#include "region/region_field.h"

namespace vfsd {
namespace {

// The sphere tool's u = (r − r_i)/(r_o − r_i), clamped: its s at the start.
std::vector<double> sphere_tool_field(const SphereTool& tool, const std::vector<Vec3>& positions) {
    std::vector<double> s(positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v)
        s[v] = std::clamp((glm::length(positions[v] - tool.centre) - tool.r_inner) / (tool.r_outer - tool.r_inner), 0.0,
                          1.0);
    return s;
}

// The far end of the moving part (s < 1) along the curve's start tangent, as a
// signed distance from c(0): where the twist's plane ẽ = 0 goes by default.
// A zero start tangent (eq. 17 with the handle moved along its own plane) takes
// the direction just after t = 0, where the motion heads.
double far_end_of_moving_part(const InnerMotion& motion, const std::vector<Vec3>& positions,
                              const std::vector<double>& s) {
    const Vec3 start = motion.curve().at(0.0).position;
    const Vec3 tangent = motion.start_tangent();
    double far = 0.0;
    for (std::size_t v = 0; v < positions.size(); ++v)
        if (s[v] < 1.0) far = std::min(far, glm::dot(positions[v] - start, tangent));
    return far;
}

void warn_about_region(const Region& region, std::vector<std::string>& warnings) {
    const bool any_moves = std::any_of(region.s.begin(), region.s.end(), [](double s) { return s < 1.0; });
    const bool any_inner = std::any_of(region.s.begin(), region.s.end(), [](double s) { return s <= 0.0; });
    if (!any_moves)
        warnings.push_back("region: s is 1 everywhere, so nothing moves");
    else if (!any_inner)
        warnings.push_back("region: no vertex has s = 0, so no part follows the curve fully");
}

void warn_about_motion(const PreparedScene& p, std::vector<std::string>& warnings) {
    const auto& positions = p.file.mesh.positions;
    if (p.motion.is_fixed_rotation() || positions.empty()) return;
    if (p.motion.curve().polygon_length() == 0.0) {
        warnings.push_back("curve: all control points coincide, so the inner region does not move");
        return;
    }
    const Vec3 start = p.motion.curve().at(0.0).position;
    const std::uint32_t nearest = nearest_vertex(positions, start);
    if (p.region.s[nearest] > 0.0)
        warnings.push_back("curve: c(0) does not lie in the inner region (s = " + std::to_string(p.region.s[nearest]) +
                           " at the nearest vertex); sec. 3 expects it there");
}

void check_coordinates(const Scene& scene, const MeshFile& file) {
    if (file.mesh.vertex_count() == 0) throw InputError(scene.mesh + ": the mesh has no vertices");
    try {
        LocalFrame::of(file.mesh.positions);  // coordinates the deformation can take, before the region's distances
    } catch (const InputError& e) {
        throw InputError(scene.mesh + ": " + e.what());
    }
}

// The motion's part of the preparation, once the region is known.
void prepare_motion(PreparedScene& p) {
    const Scene& scene = p.scene;
    p.motion = build_motion(scene.motion);
    if (!scene.motion.twist_plane && !p.motion.is_fixed_rotation())
        p.motion.set_twist_plane(far_end_of_moving_part(p.motion, p.file.mesh.positions, p.region.s));
    warn_about_motion(p, p.warnings);
}

}  // namespace

Region build_region(const RegionSpec& spec, const std::vector<Vec3>& positions, const VertexRings& rings,
                    std::vector<std::string>& warnings) {
    RegionBuild build(spec, positions, rings);
    build.advance(std::numeric_limits<double>::infinity());
    return build.take(warnings);
}

RegionBuild::RegionBuild(const RegionSpec& spec, const std::vector<Vec3>& positions, const VertexRings& rings)
    : positions_(positions), rings_(rings) {
    switch (spec.kind) {
        case RegionSpec::Kind::painted: {
            RegionField field = painted_region_field(positions, rings, select_vertices(positions, spec.inner),
                                                     select_vertices(positions, spec.outer), spec.geodesic, spec.band);
            warnings_ = std::move(field.warnings);
            region_.s = std::move(field.s);
            break;
        }
        case RegionSpec::Kind::geodesic:
            region_.s = geodesic_level_field(positions, rings, nearest_vertex(positions, spec.seed), spec.g_min,
                                             spec.g_max, spec.geodesic);
            break;
        case RegionSpec::Kind::implicit:
            region_.sphere_tool = spec.sphere;
            region_.s = sphere_tool_field(spec.sphere, positions);
            break;
        case RegionSpec::Kind::field:
            if (spec.s.size() != positions.size())
                throw InputError("region.s: " + std::to_string(spec.s.size()) + " values for a mesh of " +
                                 std::to_string(positions.size()) + " vertices");
            region_.s = spec.s;
            break;
    }
    // Eqs. (15) and (16) give the inner and outer regions; between them s is the
    // harmonic interpolation unless the scene asks for the geodesic profile.
    const bool painted_or_geodesic = spec.kind == RegionSpec::Kind::painted || spec.kind == RegionSpec::Kind::geodesic;
    blend_wanted_ = painted_or_geodesic && spec.profile == RegionSpec::Profile::harmonic;
}

bool RegionBuild::advance(double budget_ms) {
    if (!blend_wanted_) return true;
    if (!blend_) {
        blend_.emplace(positions_, rings_, std::move(region_.s));
        if (std::isfinite(budget_ms)) return false;  // the set-up is a part
    }
    if (blend_->iterate(budget_ms)) {
        region_.s = blend_->take();
        blend_.reset();
        blend_wanted_ = false;
    }
    return built();
}

Region RegionBuild::take(std::vector<std::string>& warnings) {
    if (!built()) throw std::logic_error("RegionBuild::take before the region is built");
    warn_about_region(region_, warnings_);
    warnings.insert(warnings.end(), warnings_.begin(), warnings_.end());
    return std::move(region_);
}

Deformation PreparedScene::start_deformation() const& {
    return Deformation(file.mesh.positions, rings, region, motion, scene.options);
}

Deformation PreparedScene::start_deformation() && {
    return Deformation(std::move(file.mesh.positions), std::move(rings), std::move(region), std::move(motion),
                       scene.options);
}

PreparedScene prepare_scene(const Scene& scene) { return prepare_scene(scene, load_mesh_file(scene.mesh)); }

PreparedScene prepare_scene(const Scene& scene, MeshFile file) {
    check_coordinates(scene, file);
    PreparedScene p;
    p.scene = scene;
    p.file = std::move(file);
    if (std::string turned = turned_triangles_warning(p.file); !turned.empty()) p.warnings.push_back(std::move(turned));
    p.rings = build_vertex_rings(p.file.mesh);
    p.region = build_region(scene.region, p.file.mesh.positions, p.rings, p.warnings);
    prepare_motion(p);
    return p;
}

PreparedScene prepare_scene(const Scene& scene, MeshFile file, VertexRings rings, Region region) {
    check_coordinates(scene, file);
    if (rings.vertex_count() != file.mesh.vertex_count() ||
        (!region.sphere_tool && region.s.size() != file.mesh.vertex_count()))
        throw InputError(scene.mesh + ": the rings or the region do not match the mesh");
    PreparedScene p;
    p.scene = scene;
    p.file = std::move(file);
    p.rings = std::move(rings);
    p.region = std::move(region);
    warn_about_region(p.region, p.warnings);
    prepare_motion(p);
    return p;
}

}  // namespace vfsd
