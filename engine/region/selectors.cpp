#include "region/selectors.h"

#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "base/error.h"

namespace vfsd {
namespace {

// Reads exactly `count` finite numbers from j, or throws naming `where`.
std::vector<double> read_numbers(const nlohmann::json& j, std::size_t count, const std::string& where,
                                 const char* layout) {
    const std::string expected = where + ": expected " + std::to_string(count) + " numbers " + layout;
    if (!j.is_array() || j.size() != count) throw InputError(expected);
    std::vector<double> out;
    out.reserve(count);
    for (const auto& x : j) {
        if (!x.is_number() || !std::isfinite(x.get<double>())) throw InputError(expected);
        out.push_back(x.get<double>());
    }
    return out;
}

std::vector<std::uint32_t> read_indices(const nlohmann::json& j, const std::string& where) {
    if (!j.is_array()) throw InputError(where + ": expected an array of vertex indices");
    std::vector<std::uint32_t> out;
    out.reserve(j.size());
    for (const auto& x : j) {
        if (!x.is_number_integer() || x.get<std::int64_t>() < 0 || x.get<std::int64_t>() > 0xffffffffLL)
            throw InputError(where + ": vertex indices must be non-negative integers");
        out.push_back(static_cast<std::uint32_t>(x.get<std::int64_t>()));
    }
    return out;
}

Selector parse_one(const nlohmann::json& j, const std::string& where) {
    if (!j.is_object() || j.size() != 1)
        throw InputError(where + ": expected an object with one key: sphere, box, halfspace or vertices");
    const std::string key = j.begin().key();
    const nlohmann::json& v = j.begin().value();
    const std::string at = where + "." + key;
    Selector s;
    if (key == "sphere") {
        const auto n = read_numbers(v, 4, at, "[cx,cy,cz,radius]");
        s = {SelectorKind::sphere, Vec3(n[0], n[1], n[2]), Vec3(0.0), n[3], {}};
        if (n[3] < 0.0) throw InputError(at + ": radius must be >= 0");
    } else if (key == "box") {
        const auto n = read_numbers(v, 6, at, "[x0,y0,z0,x1,y1,z1]");
        s = {SelectorKind::box, Vec3(n[0], n[1], n[2]), Vec3(n[3], n[4], n[5]), 0.0, {}};
        if (n[3] < n[0] || n[4] < n[1] || n[5] < n[2]) throw InputError(at + ": needs x0 <= x1, y0 <= y1, z0 <= z1");
    } else if (key == "halfspace") {
        const auto n = read_numbers(v, 4, at, "[nx,ny,nz,d]");
        s = {SelectorKind::halfspace, Vec3(n[0], n[1], n[2]), Vec3(0.0), n[3], {}};
        if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0) throw InputError(at + ": the normal must not be zero");
    } else if (key == "vertices") {
        s.kind = SelectorKind::vertices;
        s.vertices = read_indices(v, at);
    } else {
        throw InputError(where + ": unknown selector \"" + key + "\" (expected sphere, box, halfspace or vertices)");
    }
    return s;
}

bool contains(const Selector& s, const Vec3& p) {
    switch (s.kind) {
        case SelectorKind::sphere: return glm::length(p - s.a) <= s.value;
        case SelectorKind::box:
            return p.x >= s.a.x && p.y >= s.a.y && p.z >= s.a.z && p.x <= s.b.x && p.y <= s.b.y && p.z <= s.b.z;
        case SelectorKind::halfspace: return glm::dot(s.a, p) >= s.value;
        case SelectorKind::vertices: return false;  // handled by index
    }
    return false;
}

}  // namespace

std::vector<Selector> parse_selectors(const nlohmann::json& json, const std::string& field) {
    std::vector<Selector> out;
    if (!json.is_array()) {
        out.push_back(parse_one(json, field));
        return out;
    }
    for (std::size_t i = 0; i < json.size(); ++i)
        out.push_back(parse_one(json[i], field + "[" + std::to_string(i) + "]"));
    return out;
}

std::vector<std::uint8_t> select_vertices(const std::vector<Vec3>& positions, const std::vector<Selector>& selectors) {
    std::vector<std::uint8_t> mask(positions.size(), 0);
    for (const Selector& s : selectors) {
        if (s.kind == SelectorKind::vertices) {
            for (std::uint32_t v : s.vertices) {
                if (v >= positions.size())
                    throw InputError("selector vertex " + std::to_string(v) + " out of range (mesh has " +
                                     std::to_string(positions.size()) + " vertices)");
                mask[v] = 1;
            }
            continue;
        }
        for (std::size_t v = 0; v < positions.size(); ++v)
            if (contains(s, positions[v])) mask[v] = 1;
    }
    return mask;
}

std::uint32_t nearest_vertex(const std::vector<Vec3>& positions, Vec3 point) {
    if (positions.empty()) throw InputError("nearest vertex: the mesh has no vertices");
    if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z))
        throw InputError("nearest vertex: the point is not finite");
    std::uint32_t best = 0;
    double best_d2 = std::numeric_limits<double>::infinity();
    for (std::uint32_t v = 0; v < positions.size(); ++v) {
        const Vec3 d = positions[v] - point;
        const double d2 = glm::dot(d, d);
        if (d2 < best_d2) {
            best_d2 = d2;
            best = v;
        }
    }
    return best;
}

}  // namespace vfsd
