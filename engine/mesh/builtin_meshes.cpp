#include "mesh/builtin_meshes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "base/error.h"
#include "mesh/subdivision.h"

namespace vfsd {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// Default resolutions: their vertex counts are listed in builtin_meshes.h.
constexpr int kBoxDefault = 19;
constexpr int kBarDefault = 16;
constexpr int kCylinderDefault = 103;
constexpr int kSphereDefault = 5;

void check_resolution(const std::string& name, int resolution, int min, int max) {
    if (resolution < min || resolution > max)
        throw InputError("builtin:" + name + ": resolution " + std::to_string(resolution) + " is outside [" +
                         std::to_string(min) + ", " + std::to_string(max) + "] (0 selects the default)");
}

// The surface of an axis-aligned box centred at the origin with `size` and
// `segments` grid cells per axis: six regular grids sharing their edges.
// Each square cell is split along the same diagonal, so interior vertices have valence 6.
TriangleMesh grid_box(const Vec3& size, const std::array<int, 3>& segments) {
    const int nx = segments[0], ny = segments[1], nz = segments[2];
    // Lattice index -> vertex index, filled only on the surface.
    std::vector<std::uint32_t> index(static_cast<std::size_t>(nx + 1) * (ny + 1) * (nz + 1), kNone);
    TriangleMesh mesh;
    auto vertex = [&](std::array<int, 3> c) {
        const std::size_t key = (static_cast<std::size_t>(c[2]) * (ny + 1) + c[1]) * (nx + 1) + c[0];
        if (index[key] == kNone) {
            index[key] = static_cast<std::uint32_t>(mesh.positions.size());
            Vec3 p;
            for (int d = 0; d < 3; ++d) p[d] = size[d] * (static_cast<double>(c[d]) / segments[d] - 0.5);
            mesh.positions.push_back(p);
        }
        return index[key];
    };
    for (int d = 0; d < 3; ++d) {
        // Face axes (u, v) with u x v = +e_d, so the face at the high side winds outward as is.
        const int u = (d + 1) % 3, v = (d + 2) % 3;
        for (int side = 0; side < 2; ++side) {
            for (int j = 0; j < segments[v]; ++j) {
                for (int i = 0; i < segments[u]; ++i) {
                    std::array<int, 3> c{};
                    c[d] = side * segments[d];
                    auto at = [&](int di, int dj) {
                        c[u] = i + di;
                        c[v] = j + dj;
                        return vertex(c);
                    };
                    const std::uint32_t a = at(0, 0), b = at(1, 0), e = at(1, 1), f = at(0, 1);
                    if (side == 1) {
                        mesh.triangles.push_back({a, b, e});
                        mesh.triangles.push_back({a, e, f});
                    } else {
                        mesh.triangles.push_back({a, e, b});
                        mesh.triangles.push_back({a, f, e});
                    }
                }
            }
        }
    }
    return mesh;
}

// A closed ring of vertices around the z axis: its first index and its angles
// theta_i = 2 pi (i + phase) / count.
struct Ring {
    std::uint32_t first;
    std::uint32_t count;
    double phase;
    double angle(std::uint32_t i) const { return 2.0 * kPi * (i + phase) / count; }
};

Ring add_ring(TriangleMesh& mesh, std::uint32_t count, double phase, double radius, double z) {
    Ring ring{static_cast<std::uint32_t>(mesh.positions.size()), count, phase};
    for (std::uint32_t i = 0; i < count; ++i) {
        const double t = ring.angle(i);
        mesh.positions.push_back(Vec3(radius * std::cos(t), radius * std::sin(t), z));
    }
    return ring;
}

// Triangulates the strip between two rings by merging their vertices in angular
// order (each step advances the ring whose next vertex comes first). The strip is
// oriented so that going from ring a to ring b and along increasing angle is
// counter-clockwise seen from outside. A ring of one vertex is a fan apex.
void stitch_rings(TriangleMesh& mesh, const Ring& a, const Ring& b) {
    auto ia = [&](std::uint32_t i) { return a.first + i % a.count; };
    auto ib = [&](std::uint32_t j) { return b.first + j % b.count; };
    if (b.count == 1) {
        for (std::uint32_t i = 0; i < a.count; ++i) mesh.triangles.push_back({ia(i), ia(i + 1), b.first});
        return;
    }
    if (a.count == 1) {
        for (std::uint32_t j = 0; j < b.count; ++j) mesh.triangles.push_back({a.first, ib(j + 1), ib(j)});
        return;
    }
    // Start ring b at its last vertex at or before a's first angle; unwrap its angles from there.
    const double start = a.angle(0);
    std::uint32_t j0 = b.count - 1;
    double base = b.angle(j0) - 2.0 * kPi;
    for (std::uint32_t j = 0; j < b.count; ++j)
        if (b.angle(j) <= start + 1e-12) j0 = j, base = b.angle(j);
    auto angle_b = [&](std::uint32_t j) { return base + 2.0 * kPi * j / b.count; };
    std::uint32_t i = 0, j = 0;
    while (i < a.count || j < b.count) {
        const bool advance_a = j == b.count || (i < a.count && a.angle(i + 1) <= angle_b(j + 1));
        if (advance_a) {
            mesh.triangles.push_back({ia(i), ia(i + 1), ib(j0 + j)});
            ++i;
        } else {
            mesh.triangles.push_back({ia(i), ib(j0 + j + 1), ib(j0 + j)});
            ++j;
        }
    }
}

// A capped cylinder along z, centred at the origin. The side is a stack of rings of
// `around` vertices, alternate rings rotated by half a step and spaced sqrt(3)/2 of
// the circumferential step apart, so the side triangles are nearly equilateral.
// Each cap is a set of concentric rings of proportionally fewer vertices around a
// centre vertex, with the same radial spacing.
TriangleMesh capped_cylinder(double radius, double length, int around) {
    const double step = 2.0 * kPi * radius / around;
    const double row = 0.5 * std::sqrt(3.0) * step;
    const int rows = std::max(1, static_cast<int>(std::lround(length / row)));
    const int cap_rings = std::max(1, static_cast<int>(std::lround(radius / row)));
    const auto m = static_cast<std::uint32_t>(around);

    TriangleMesh mesh;
    std::vector<Ring> side;
    for (int k = 0; k <= rows; ++k)
        side.push_back(add_ring(mesh, m, 0.5 * (k % 2), radius, length * (static_cast<double>(k) / rows - 0.5)));
    for (int k = 0; k < rows; ++k) stitch_rings(mesh, side[k], side[k + 1]);

    // Cap rings from the rim inward; the rim is the side's end ring.
    auto cap = [&](const Ring& rim, double z, bool top) {
        Ring outer = rim;
        for (int j = cap_rings - 1; j >= 0; --j) {
            const auto count = j == 0 ? 1u : static_cast<std::uint32_t>(std::lround(double(m) * j / cap_rings));
            const Ring inner = add_ring(mesh, count, std::fmod(rim.phase + 0.5 * ((cap_rings - j) % 2), 1.0), radius * j / cap_rings, z);
            // Top cap: outward +z, so going outer -> inner is the "a -> b" direction.
            if (top)
                stitch_rings(mesh, outer, inner);
            else
                stitch_rings(mesh, inner, outer);
            outer = inner;
        }
    };
    cap(side.front(), -0.5 * length, false);
    cap(side.back(), 0.5 * length, true);
    return mesh;
}

// An icosphere of radius 1: the icosahedron, each triangle split into four
// `levels` times, new vertices projected onto the sphere.
TriangleMesh icosphere(int levels) {
    const double t = 0.5 * (1.0 + std::sqrt(5.0));
    TriangleMesh mesh;
    const double base[12][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (const auto& p : base) mesh.positions.push_back(glm::normalize(Vec3(p[0], p[1], p[2])));
    mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                      {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    const auto on_sphere = [](const Vec3& a, const Vec3& b) { return glm::normalize(a + b); };
    for (int level = 0; level < levels; ++level) mesh = subdivide_midpoints(mesh, on_sphere);
    return mesh;
}

}  // namespace

TriangleMesh make_builtin_mesh(const std::string& name, int resolution) {
    if (name == "box") {
        // 1 x 1 x 1.2; `resolution` cells across x and y.
        const int n = resolution == 0 ? kBoxDefault : resolution;
        check_resolution(name, n, 1, 1000);
        return grid_box(Vec3(1.0, 1.0, 1.2), {n, n, static_cast<int>(std::lround(1.2 * n))});
    }
    if (name == "bar") {
        // 1 x 1 x 9; `resolution` cells across x and y.
        const int n = resolution == 0 ? kBarDefault : resolution;
        check_resolution(name, n, 1, 300);
        return grid_box(Vec3(1.0, 1.0, 9.0), {n, n, 9 * n});
    }
    if (name == "cylinder") {
        // Radius 0.5, length 5; `resolution` vertices around.
        const int m = resolution == 0 ? kCylinderDefault : resolution;
        check_resolution(name, m, 3, 3000);
        return capped_cylinder(0.5, 5.0, m);
    }
    if (name == "sphere") {
        // Radius 1; `resolution` subdivision levels of the icosahedron.
        const int levels = resolution == 0 ? kSphereDefault : resolution;
        check_resolution(name, levels, 1, 9);
        return icosphere(levels);
    }
    std::string known;
    for (const std::string& n : builtin_mesh_names()) known += (known.empty() ? "" : ", ") + n;
    throw InputError("unknown built-in mesh '" + name + "' (known: " + known + ")");
}

std::vector<std::string> builtin_mesh_names() { return {"box", "bar", "cylinder", "sphere"}; }

}  // namespace vfsd
