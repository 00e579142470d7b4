#include "scene/battery.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "mesh/builtin_meshes.h"
#include "mesh/geometry.h"
#include "mesh/vertex_rings.h"
#include "region/geodesic.h"
#include "region/region_field.h"
#include "scene/prepared_scene.h"

namespace vfsd {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegrees = kPi / 180.0;

// SplitMix64 (Steele, Lea, Flood 2014): small, fast, the same on every platform.
class Random {
public:
    explicit Random(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform(double a = 0.0, double b = 1.0) { return a + (b - a) * double(next() >> 11) * 0x1.0p-53; }
    std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>(uniform() * n) % n; }
    bool chance(double p) { return uniform() < p; }
    Vec3 unit_vector() {  // uniform on the sphere
        const double z = uniform(-1.0, 1.0), phi = uniform(0.0, 2.0 * kPi), r = std::sqrt(1.0 - z * z);
        return Vec3(r * std::cos(phi), r * std::sin(phi), z);
    }
    glm::dmat3 rotation(double max_angle = kPi) { return rotation_about(unit_vector(), uniform(0.0, max_angle)); }

    static glm::dmat3 rotation_about(const Vec3& axis, double angle) {
        return glm::dmat3(glm::rotate(glm::dmat4(1.0), angle, axis));
    }

private:
    std::uint64_t state_;
};

// A unit vector perpendicular to the unit vector d.
Vec3 perpendicular(const Vec3& d) {
    const Vec3 other = std::abs(d.x) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
    return glm::normalize(glm::cross(d, other));
}

double mean_edge_length(const TriangleMesh& mesh) {
    double sum = 0.0;
    for (const Triangle& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) sum += glm::length(mesh.positions[t[(k + 1) % 3]] - mesh.positions[t[k]]);
    return mesh.triangles.empty() ? 0.0 : sum / (3.0 * mesh.triangles.size());
}

// Where the inner region sits and how wide its blend region is, on the mesh at rest.
struct RegionLayout {
    std::uint32_t seed = 0;
    std::vector<double> g;  // geodesic distance from the seed
    double inner = 0.0;     // the inner region: g ≤ inner
    double width = 0.0;     // the blend region: inner < g < inner + width
    double reach = 0.0;     // the largest g
    Vec3 direction{0.0};    // the way out of the mesh at the inner region
};

RegionLayout layout_region(Random& rng, const TriangleMesh& mesh, const VertexRings& rings) {
    const auto& p = mesh.positions;
    const double diagonal = bounding_box(p).diagonal(), h = mean_edge_length(mesh);
    RegionLayout r;
    r.seed = rng.below(static_cast<std::uint32_t>(p.size()));
    r.g = geodesic_distance(p, rings, {r.seed});
    double& reach = r.reach;
    for (double d : r.g)
        if (std::isfinite(d)) reach = std::max(reach, d);
    r.inner = std::max(2.0 * h, rng.uniform(0.04, 0.15) * diagonal);
    r.width = std::max(8.0 * h, rng.uniform(0.08, 0.3) * diagonal);
    if (r.inner + r.width > 0.8 * reach) {  // keep an outer region
        const double shrink = 0.8 * reach / (r.inner + r.width);
        r.inner *= shrink, r.width *= shrink;
    }
    // Out of the mesh: from the blend region's centroid through the seed, or
    // along the normal where the blend region surrounds the seed evenly.
    Vec3 centroid(0.0);
    int count = 0;
    for (std::size_t v = 0; v < p.size(); ++v)
        if (r.g[v] > r.inner && r.g[v] < r.inner + r.width) centroid += p[v], ++count;
    const Vec3 away = count > 0 ? p[r.seed] - centroid / double(count) : Vec3(0.0);
    if (glm::length(away) > 0.25 * r.inner) {
        r.direction = glm::normalize(away);
    } else {
        std::vector<Vec3> normals;
        vertex_normals(p, rings, normals);
        r.direction = glm::length(normals[r.seed]) > 0.0 ? glm::normalize(normals[r.seed]) : rng.unit_vector();
    }
    const Vec3 axis = perpendicular(r.direction);
    r.direction = Random::rotation_about(Random::rotation_about(r.direction, rng.uniform(0, 2 * kPi)) * axis,
                                         rng.uniform(0.0, 30.0 * kDegrees)) * r.direction;
    return r;
}

std::string set_region(Random& rng, const RegionLayout& r, const TriangleMesh& mesh, RegionSpec& spec) {
    const auto& p = mesh.positions;
    const Vec3 centre = p[r.seed];
    switch (rng.below(4)) {
        case 0:  // eq. (15) about the seed
            spec.kind = RegionSpec::Kind::geodesic;
            spec.seed = centre;
            spec.g_min = r.inner;
            spec.g_max = r.inner + r.width;
            return "geodesic";
        case 1: {  // eq. (16) between a ball and a half-space towards the far end
            spec.kind = RegionSpec::Kind::painted;
            spec.inner = {Selector{SelectorKind::sphere, centre, Vec3(0.0), r.inner, {}}};
            const auto far = static_cast<std::size_t>(
                std::max_element(r.g.begin(), r.g.end(), [](double a, double b) { return a < b || !std::isfinite(a); }) -
                r.g.begin());
            const Vec3 back = glm::normalize(p[far] - centre);
            double extent = 0.0;  // how far the mesh reaches that way
            for (const Vec3& x : p) extent = std::max(extent, glm::dot(back, x - centre));
            const double behind = std::min(r.inner + r.width, r.inner + 0.8 * (extent - r.inner));
            spec.outer = {Selector{SelectorKind::halfspace, back, Vec3(0.0), behind + glm::dot(back, centre), {}}};
            return "selectors";
        }
        case 2: {  // eq. (16) between painted vertex lists
            spec.kind = RegionSpec::Kind::painted;
            Selector inner{SelectorKind::vertices, {}, {}, 0.0, {}}, outer = inner;
            for (std::uint32_t v = 0; v < p.size(); ++v) {
                if (r.g[v] <= r.inner) inner.vertices.push_back(v);
                else if (r.g[v] >= r.inner + r.width) outer.vertices.push_back(v);
            }
            spec.inner = {inner};
            spec.outer = {outer};
            return "vertex-lists";
        }
        default:  // s painted directly: a ramp in the geodesic distance from the seed, eased
            spec.kind = RegionSpec::Kind::field;
            for (const double g : r.g) {
                const double ramp = std::clamp((g - r.inner) / r.width, 0.0, 1.0);
                spec.s.push_back(ramp * ramp * (3.0 - 2.0 * ramp));
            }
            return "painted-s";
    }
}

// 1–3 cubic pieces joined with a common tangent, each turning by its share of
// the bend about a random axis across the tangent; the chord of a piece bisects
// its end tangents, as a circular arc's does.
std::vector<Vec3> bent_curve(Random& rng, Vec3 start, Vec3 tangent, int pieces, double length, double bend) {
    std::vector<Vec3> points = {start};
    for (int i = 0; i < pieces; ++i) {
        const double piece = length / pieces, turn = bend / pieces;
        const Vec3 axis = Random::rotation_about(tangent, rng.uniform(0, 2 * kPi)) * perpendicular(tangent);
        const Vec3 next_tangent = Random::rotation_about(axis, turn) * tangent;
        const Vec3 chord = glm::normalize(tangent + next_tangent);
        const Vec3 end = start + piece * chord;
        points.push_back(start + (piece / 3.0) * tangent);
        points.push_back(end - (piece / 3.0) * next_tangent);
        points.push_back(end);
        start = end, tangent = next_tangent;
    }
    return points;
}

Placement random_placement(Random& rng, double diagonal) {
    Placement p;
    p.rotation = rng.rotation();
    if (rng.chance(0.25)) p.rotation = p.rotation * glm::dmat3(-1, 0, 0, 0, 1, 0, 0, 0, 1);
    p.scale = std::pow(10.0, rng.uniform(-2.0, 2.0));
    p.offset = rng.unit_vector() * (rng.uniform(0.0, 100.0) * diagonal * p.scale);
    return p;
}

std::string short_name(const std::string& source) {
    std::string name = source;
    if (name.rfind("builtin:", 0) == 0) name = name.substr(8);
    const auto slash = name.find_last_of('/');
    if (slash != std::string::npos) name = name.substr(slash + 1);
    const auto dot = name.find_last_of('.');
    if (dot != std::string::npos) name = name.substr(0, dot);
    std::replace(name.begin(), name.end(), ':', '_');
    return name;
}

}  // namespace

std::string battery_mesh_unusable(const MeshFile& file, bool any_surface) {
    const TriangleMesh& mesh = file.mesh;
    const std::size_t n = mesh.vertex_count();
    if (n < kBatteryMinVertices)
        return std::to_string(n) + " vertices (fewer than " + std::to_string(kBatteryMinVertices) + ")";
    if (any_surface) return "";
    const VertexRings rings = build_vertex_rings(mesh);
    for (std::uint32_t v = 0; v < n; ++v)
        if (!rings.is_closed(v)) return "open (vertex " + std::to_string(v) + " is on a border or not manifold)";
    if (file.turned_triangles > 0)
        return "wound inconsistently (" + std::to_string(file.turned_triangles) + " triangles turned)";
    std::vector<bool> reached(n, false);
    std::vector<std::uint32_t> queue = {0};
    reached[0] = true;
    for (std::size_t i = 0; i < queue.size(); ++i)
        for (std::uint32_t k = rings.begin(queue[i]); k < rings.end(queue[i]); ++k)
            if (!reached[rings.neighbours[k]]) reached[rings.neighbours[k]] = true, queue.push_back(rings.neighbours[k]);
    if (queue.size() < n) return "more than one piece";
    return "";
}

std::vector<std::string> battery_mesh_sources(const std::vector<std::string>& mesh_files, bool fine_builtins) {
    std::vector<std::string> sources = {"builtin:box:8", "builtin:cylinder:24", "builtin:sphere:3", "builtin:bar:5"};
    if (fine_builtins)
        for (const char* fine : {"builtin:box:18", "builtin:cylinder:64", "builtin:sphere:5", "builtin:bar:12"})
            sources.push_back(fine);
    sources.insert(sources.end(), mesh_files.begin(), mesh_files.end());
    return sources;
}

BatteryScene generate_battery_scene(std::uint64_t seed, int index, const std::vector<std::string>& mesh_sources,
                                    double amplitude) {
    Random rng(seed * 0x9E3779B97F4A7C15ull + std::uint64_t(index) * 0xD1B54A32D192ED03ull + 1);
    BatteryScene b;
    b.mesh_source = mesh_sources.at(std::size_t(index) % mesh_sources.size());
    b.mesh = load_mesh_file(b.mesh_source);
    const TriangleMesh& mesh = b.mesh.mesh;
    const VertexRings rings = build_vertex_rings(mesh);
    RegionLayout layout = layout_region(rng, mesh, rings);

    Scene scene;
    scene.mesh = b.mesh_source;
    // The blend region must be at least kBatteryBlendRings rings wide everywhere;
    // where the triangles are large it is widened (the same random choices) or,
    // when the mesh is too short for that, the inner region is made smaller.
    // Where that does not make room either (a coarse part), the region is laid
    // out about another seed, up to kLayouts times.
    constexpr int kLayouts = 12;
    for (int layouts = 1;; ++layouts) {
        for (int attempt = 0;; ++attempt) {
            Random trial = rng;
            scene.region = RegionSpec{};
            b.region_kind = set_region(trial, layout, mesh, scene.region);
            std::vector<std::string> warnings;
            b.blend_rings = blend_ring_width(build_region(scene.region, mesh.positions, rings, warnings).s, rings);
            if (b.blend_rings >= kBatteryBlendRings || attempt == 6) {
                rng = trial;
                break;
            }
            const double wider = layout.width * 1.2 * kBatteryBlendRings / std::max(1, b.blend_rings);
            layout.inner = std::max(0.25 * layout.inner, std::min(layout.inner, 0.8 * layout.reach - wider));
            layout.width = std::min(wider, 0.8 * layout.reach - layout.inner);
        }
        if (b.blend_rings >= kBatteryBlendRings || layouts == kLayouts) break;
        layout = layout_region(rng, mesh, rings);
    }
    const Vec3 start = mesh.positions[layout.seed];
    const double amp = amplitude;
    const double length = amp * rng.uniform(0.2, 1.0) * 2.0 * layout.inner;  // up to the inner region's size
    if (rng.chance(0.25)) {  // a handle moved and turned (sec. 6.2)
        b.motion_kind = "handle";
        scene.motion.curve.is_handle = true;
        const Vec3 w = perpendicular(layout.direction);
        scene.motion.curve.from = {start, layout.direction, w};
        const glm::dmat3 turn = rng.rotation(amp * 90.0 * kDegrees);
        const Vec3 move = glm::normalize(layout.direction + 0.7 * rng.unit_vector());
        scene.motion.curve.to = {start + length * move, turn * layout.direction, turn * w};
        b.bend_degrees = std::acos(std::clamp(glm::dot(layout.direction, turn * layout.direction), -1.0, 1.0)) / kDegrees;
    } else {
        const int pieces = 1 + static_cast<int>(rng.below(3));
        b.motion_kind = "curve" + std::to_string(pieces);
        b.bend_degrees = amp * rng.uniform(0.0, 180.0);
        scene.motion.curve.bezier = bent_curve(rng, start, layout.direction, pieces, length, b.bend_degrees * kDegrees);
        scene.motion.twist_degrees[1] = b.twist_degrees = amp * rng.uniform(-180.0, 180.0);
        if (rng.chance(0.3)) scene.motion.inner_motion = InnerMotionMode::Translation;
    }
    b.move_over_inner = length / (2.0 * layout.inner);

    b.placement = random_placement(rng, bounding_box(mesh.positions).diagonal());
    b.scene = place_scene(scene, b.placement);
    place_mesh(b.mesh.mesh, b.placement);
    char prefix[16];
    std::snprintf(prefix, sizeof prefix, "%04d-", index);
    b.name = prefix + short_name(b.mesh_source) + "-" + b.region_kind + "-" + b.motion_kind;
    return b;
}

}  // namespace vfsd
