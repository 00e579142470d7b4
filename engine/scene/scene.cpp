#include "scene/scene.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/error.h"

namespace vfsd {
namespace {

using json = nlohmann::json;

// Reads scene fields with errors that name the field.
class Reader {
public:
    explicit Reader(std::string name) : name_(std::move(name)) {}

    [[noreturn]] void fail(const std::string& field, const std::string& what) const {
        throw InputError(name_ + ": " + field + ": " + what);
    }
    const json& member(const json& j, const char* key, const std::string& field) const {
        if (!j.is_object() || !j.contains(key)) fail(field, std::string("missing '") + key + "'");
        return j.at(key);
    }
    double number(const json& j, const std::string& field) const {
        if (!j.is_number()) fail(field, "expected a number");
        const double v = j.get<double>();
        if (!std::isfinite(v)) fail(field, "expected a finite number");
        return v;
    }
    int integer(const json& j, const std::string& field, int min, int max) const {
        if (!j.is_number_integer()) fail(field, "expected an integer");
        const auto v = j.get<long long>();
        if (v < min || v > max) fail(field, "expected a value in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
        return static_cast<int>(v);
    }
    Vec3 vec3(const json& j, const std::string& field) const {
        if (!j.is_array() || j.size() != 3) fail(field, "expected [x, y, z]");
        return {number(j[0], field), number(j[1], field), number(j[2], field)};
    }
    std::string string(const json& j, const std::string& field) const {
        if (!j.is_string()) fail(field, "expected a string");
        return j.get<std::string>();
    }

private:
    std::string name_;
};

RegionSpec parse_region(const Reader& in, const json& j) {
    RegionSpec r;
    const std::string kind = in.string(in.member(j, "kind", "region"), "region.kind");
    if (kind == "painted") {
        r.kind = RegionSpec::Kind::painted;
        r.inner = parse_selectors(in.member(j, "inner", "region"), "region.inner");
        r.outer = parse_selectors(in.member(j, "outer", "region"), "region.outer");
        if (j.contains("band")) {
            r.band = in.number(j["band"], "region.band");
            if (!(r.band >= 0.0)) in.fail("region.band", "expected a distance >= 0");
        }
    } else if (kind == "geodesic") {
        r.kind = RegionSpec::Kind::geodesic;
        r.seed = in.vec3(in.member(j, "seed", "region"), "region.seed");
        r.g_min = in.number(in.member(j, "g_min", "region"), "region.g_min");
        r.g_max = in.number(in.member(j, "g_max", "region"), "region.g_max");
        if (!(0.0 <= r.g_min && r.g_min < r.g_max)) in.fail("region", "expected 0 <= g_min < g_max");
    } else if (kind == "implicit") {
        r.kind = RegionSpec::Kind::implicit;
        r.sphere.centre = in.vec3(in.member(j, "center", "region"), "region.center");
        r.sphere.r_inner = in.number(in.member(j, "r_inner", "region"), "region.r_inner");
        r.sphere.r_outer = in.number(in.member(j, "r_outer", "region"), "region.r_outer");
        if (!(0.0 <= r.sphere.r_inner && r.sphere.r_inner < r.sphere.r_outer))
            in.fail("region", "expected 0 <= r_inner < r_outer");
    } else if (kind == "field") {
        r.kind = RegionSpec::Kind::field;
        const json& s = in.member(j, "s", "region");
        if (!s.is_array()) in.fail("region.s", "expected an array with one value per vertex");
        r.s.reserve(s.size());
        for (const json& v : s) {
            const double x = in.number(v, "region.s");
            if (x < 0.0 || x > 1.0) in.fail("region.s", "values must lie in [0, 1]");
            r.s.push_back(x);
        }
    } else {
        in.fail("region.kind", "expected \"painted\", \"geodesic\", \"implicit\" or \"field\", got \"" + kind + "\"");
    }
    if (j.contains("smoothing_iterations"))
        r.geodesic.smoothing_iterations = in.integer(j["smoothing_iterations"], "region.smoothing_iterations", 0, 1000);
    if (j.contains("profile")) {
        const std::string profile = in.string(j["profile"], "region.profile");
        if (profile == "harmonic") r.profile = RegionSpec::Profile::harmonic;
        else if (profile == "geodesic") r.profile = RegionSpec::Profile::geodesic;
        else in.fail("region.profile", "expected \"harmonic\" or \"geodesic\", got \"" + profile + "\"");
    }
    return r;
}

HandleFrame parse_frame(const Reader& in, const json& j, const std::string& field) {
    HandleFrame f;
    f.position = in.vec3(in.member(j, "position", field), field + ".position");
    f.normal = in.vec3(in.member(j, "normal", field), field + ".normal");
    f.binormal = in.vec3(in.member(j, "binormal", field), field + ".binormal");
    if (glm::length(f.normal) == 0.0 || glm::length(f.binormal) == 0.0) in.fail(field, "normal and binormal must be non-zero");
    f.normal = glm::normalize(f.normal);
    // Accept a binormal that is not exactly perpendicular: keep its part ⟂ m.
    f.binormal -= glm::dot(f.binormal, f.normal) * f.normal;
    if (glm::length(f.binormal) < 1e-9) in.fail(field, "binormal must not be parallel to the normal");
    f.binormal = glm::normalize(f.binormal);
    return f;
}

CurveSpec parse_curve(const Reader& in, const json& j) {
    CurveSpec c;
    if (j.contains("bezier")) {
        const json& points = j["bezier"];
        if (!points.is_array()) in.fail("curve.bezier", "expected an array of [x, y, z] points");
        for (std::size_t i = 0; i < points.size(); ++i)
            c.bezier.push_back(in.vec3(points[i], "curve.bezier[" + std::to_string(i) + "]"));
        if (c.bezier.size() < 4 || (c.bezier.size() - 1) % 3 != 0)
            in.fail("curve.bezier", "expected 3k+1 control points (k >= 1), got " + std::to_string(c.bezier.size()));
    } else if (j.contains("handle")) {
        c.is_handle = true;
        c.from = parse_frame(in, in.member(j["handle"], "from", "curve.handle"), "curve.handle.from");
        c.to = parse_frame(in, in.member(j["handle"], "to", "curve.handle"), "curve.handle.to");
    } else {
        in.fail("curve", "expected \"bezier\" or \"handle\"");
    }
    return c;
}

// The keys of MotionSpec: "curve" (required) and the motion settings around it.
MotionSpec parse_motion(const Reader& in, const json& j) {
    MotionSpec m;
    m.curve = parse_curve(in, in.member(j, "curve", "scene"));
    if (j.contains("inner_motion")) {
        const std::string mode = in.string(j["inner_motion"], "inner_motion");
        if (mode == "rotation") m.inner_motion = InnerMotionMode::Rotation;
        else if (mode == "translation") m.inner_motion = InnerMotionMode::Translation;
        else in.fail("inner_motion", "expected \"rotation\" or \"translation\", got \"" + mode + "\"");
    }
    if (j.contains("twist_degrees")) {
        const json& t = j["twist_degrees"];
        if (!t.is_array() || t.size() != 2) in.fail("twist_degrees", "expected [alpha0, alpha1]");
        m.twist_degrees[0] = in.number(t[0], "twist_degrees");
        m.twist_degrees[1] = in.number(t[1], "twist_degrees");
    }
    if (j.contains("twist_plane")) {
        const json& plane = j["twist_plane"];
        if (plane == "curve") m.twist_plane = 0.0;
        else if (plane.is_number()) m.twist_plane = in.number(plane, "twist_plane");
        else if (plane != "region") in.fail("twist_plane", "expected \"region\", \"curve\" or a number");
    }
    if (j.contains("stream_origin") && j["stream_origin"] != "curve") {
        if (!j["stream_origin"].is_array()) in.fail("stream_origin", "expected \"curve\" or [x, y, z]");
        m.stream_origin = in.vec3(j["stream_origin"], "stream_origin");
    }
    return m;
}

void parse_options(const Reader& in, const json& j, Scene& scene) {
    if (j.contains("steps")) scene.options.steps = in.integer(j["steps"], "steps", 1, 1000000);
    // A file that gives neither takes error-controlled steps; one that gives
    // only "steps" keeps the fixed steps it asks for.
    scene.options.tolerance = j.contains("steps") ? 0.0 : kSceneTolerance;
    if (j.contains("tolerance")) {
        scene.options.tolerance = in.number(j["tolerance"], "tolerance");
        if (!(scene.options.tolerance >= 0.0 && scene.options.tolerance <= 0.1))
            in.fail("tolerance", "expected 0 (fixed steps) to 0.1 of the diagonal");
    }
    if (j.contains("smoothing_steps")) scene.options.smoothing_steps = in.integer(j["smoothing_steps"], "smoothing_steps", 0, 10000);
    if (j.contains("stream_gauge")) {
        const json& gauge = j["stream_gauge"];
        if (gauge != "fit" && gauge != "paper") in.fail("stream_gauge", "expected \"fit\" or \"paper\"");
        scene.options.fit_stream_gauge = gauge == "fit";
    }
    if (j.contains("smoothing")) {
        const json& smoothing = j["smoothing"];
        if (smoothing != "space" && smoothing != "tangent") in.fail("smoothing", "expected \"space\" or \"tangent\"");
        scene.options.tangent_smoothing = smoothing == "tangent";
    }
    if (j.contains("keep_volume")) {
        if (!j["keep_volume"].is_boolean()) in.fail("keep_volume", "expected true or false");
        scene.options.keep_volume = j["keep_volume"].get<bool>();
    }
    if (j.contains("fold_repair")) {
        if (!j["fold_repair"].is_boolean()) in.fail("fold_repair", "expected true or false");
        scene.options.repair_folds = j["fold_repair"].get<bool>();
    }
    if (j.contains("fold_refinement"))
        scene.options.fold_refinements = in.integer(j["fold_refinement"], "fold_refinement", 0, kMaxFoldRefinements);
    if (j.contains("target_time")) {
        scene.target_time = in.number(j["target_time"], "target_time");
        if (scene.target_time < 0.0 || scene.target_time > 1.0) in.fail("target_time", "expected a time in [0, 1]");
    }
    if (j.contains("up")) {
        if (j["up"] != "z" && j["up"] != "y") in.fail("up", "expected \"z\" or \"y\"");
        scene.up_axis = j["up"] == "y" ? 'y' : 'z';
    }
}

}  // namespace

Scene parse_scene(const json& j, const std::string& base_dir, const std::string& name) {
    const Reader in(name);
    if (!j.is_object()) in.fail("scene", "expected a JSON object");
    Scene scene;
    scene.mesh = in.string(in.member(j, "mesh", "scene"), "mesh");
    if (scene.mesh.rfind("builtin:", 0) != 0 && !base_dir.empty() && std::filesystem::path(scene.mesh).is_relative())
        scene.mesh = (std::filesystem::path(base_dir) / scene.mesh).lexically_normal().string();
    scene.region = parse_region(in, in.member(j, "region", "scene"));
    scene.motion = parse_motion(in, j);
    parse_options(in, j, scene);
    return scene;
}

nlohmann::json parse_scene_json(const std::string& text, const std::string& name) {
    // The callback sees every array and object as it opens, before its contents are read.
    const json::parser_callback_t limit_depth = [&name](int depth, json::parse_event_t event, json&) {
        if ((event == json::parse_event_t::object_start || event == json::parse_event_t::array_start) &&
            depth >= kMaxSceneJsonDepth)
            throw InputError(name + ": JSON nests deeper than " + std::to_string(kMaxSceneJsonDepth) + " levels");
        return true;
    };
    try {
        return json::parse(text, limit_depth);
    } catch (const json::exception& e) {
        throw InputError(name + ": not valid JSON (" + std::string(e.what()) + ")");
    }
}

Scene load_scene(const std::string& path) {
    std::ifstream file(path, std::ios::binary);
    if (!file) throw IoError(path + ": cannot open the scene file");
    std::ostringstream text;
    text << file.rdbuf();
    if (file.bad()) throw IoError(path + ": cannot read the scene file");
    return parse_scene(parse_scene_json(text.str(), path), std::filesystem::path(path).parent_path().string(), path);
}

}  // namespace vfsd

namespace vfsd {
namespace {

nlohmann::json to_json(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json frame_json(const HandleFrame& f) {
    return {{"position", to_json(f.position)}, {"normal", to_json(f.normal)}, {"binormal", to_json(f.binormal)}};
}

nlohmann::json selectors_json(const std::vector<Selector>& selectors) {
    nlohmann::json list = nlohmann::json::array();
    for (const Selector& s : selectors) {
        switch (s.kind) {
            case SelectorKind::sphere: list.push_back({{"sphere", {s.a.x, s.a.y, s.a.z, s.value}}}); break;
            case SelectorKind::box: list.push_back({{"box", {s.a.x, s.a.y, s.a.z, s.b.x, s.b.y, s.b.z}}}); break;
            case SelectorKind::halfspace: list.push_back({{"halfspace", {s.a.x, s.a.y, s.a.z, s.value}}}); break;
            case SelectorKind::vertices: list.push_back({{"vertices", s.vertices}}); break;
        }
    }
    return list;
}

nlohmann::json region_json(const RegionSpec& r) {
    switch (r.kind) {
        case RegionSpec::Kind::painted:
            return {{"kind", "painted"}, {"inner", selectors_json(r.inner)}, {"outer", selectors_json(r.outer)},
                    {"band", r.band}};
        case RegionSpec::Kind::geodesic:
            return {{"kind", "geodesic"}, {"seed", to_json(r.seed)}, {"g_min", r.g_min}, {"g_max", r.g_max}};
        case RegionSpec::Kind::implicit:
            return {{"kind", "implicit"}, {"center", to_json(r.sphere.centre)}, {"r_inner", r.sphere.r_inner},
                    {"r_outer", r.sphere.r_outer}};
        case RegionSpec::Kind::field: return {{"kind", "field"}, {"s", r.s}};
    }
    return {};
}

}  // namespace

nlohmann::json scene_to_json(const Scene& scene) {
    nlohmann::json j;
    j["mesh"] = scene.mesh;
    j["region"] = region_json(scene.region);
    if (scene.region.kind == RegionSpec::Kind::painted || scene.region.kind == RegionSpec::Kind::geodesic) {
        j["region"]["smoothing_iterations"] = scene.region.geodesic.smoothing_iterations;
        j["region"]["profile"] = scene.region.profile == RegionSpec::Profile::harmonic ? "harmonic" : "geodesic";
    }
    const MotionSpec& m = scene.motion;
    if (m.curve.is_handle) {
        j["curve"] = {{"handle", {{"from", frame_json(m.curve.from)}, {"to", frame_json(m.curve.to)}}}};
    } else {
        nlohmann::json points = nlohmann::json::array();
        for (const Vec3& p : m.curve.bezier) points.push_back(to_json(p));
        j["curve"] = {{"bezier", points}};
    }
    j["inner_motion"] = m.inner_motion == InnerMotionMode::Rotation ? "rotation" : "translation";
    j["twist_degrees"] = {m.twist_degrees[0], m.twist_degrees[1]};
    if (m.twist_plane) j["twist_plane"] = *m.twist_plane;
    else j["twist_plane"] = "region";
    if (m.stream_origin) j["stream_origin"] = to_json(*m.stream_origin);
    else j["stream_origin"] = "curve";
    j["steps"] = scene.options.steps;
    j["tolerance"] = scene.options.tolerance;
    j["smoothing_steps"] = scene.options.smoothing_steps;
    j["stream_gauge"] = scene.options.fit_stream_gauge ? "fit" : "paper";
    j["smoothing"] = scene.options.tangent_smoothing ? "tangent" : "space";
    j["keep_volume"] = scene.options.keep_volume;
    j["fold_repair"] = scene.options.repair_folds;
    j["fold_refinement"] = scene.options.fold_refinements;
    j["target_time"] = scene.target_time;
    j["up"] = std::string(1, scene.up_axis);
    return j;
}

const std::vector<SceneKey>& scene_keys() {
    static const std::vector<SceneKey> keys = {
        {"mesh", "a mesh file (relative to the scene file) or builtin:NAME[:RESOLUTION]", "required"},
        {"region", "which part moves: {\"kind\": \"painted\" | \"geodesic\" | \"implicit\" | \"field\", ...}",
         "required"},
        {"curve", "{\"bezier\": [[x,y,z], ...]} (3k+1 points) or {\"handle\": {\"from\": FRAME, \"to\": FRAME}}",
         "required"},
        {"inner_motion", "\"rotation\" (eqs. 11-13) or \"translation\" (eqs. 9-10)", "\"rotation\""},
        {"twist_degrees", "[alpha0, alpha1]: alpha(t) linear, counter-clockwise about the tangent", "[0, 0]"},
        {"twist_plane", "\"region\", \"curve\" (eq. 14 as printed) or a signed distance along the tangent",
         "\"region\""},
        {"stream_origin", "\"curve\" (eq. 10) or a point [x,y,z] that e and f are built about", "\"curve\""},
        {"stream_gauge", "\"fit\" (a gauge fitted to the blend region every step) or \"paper\"", "\"fit\""},
        {"smoothing", "\"space\" (the gradient smoothed as a vector) or \"tangent\" (as sec. 5)", "\"space\""},
        {"keep_volume", "true: the blend region's volume drift undone every step; false: as sec. 5", "true"},
        {"fold_repair", "true: a folded triangle's blend vertices placed again, every 1/20 in time; false: as sec. 5",
         "true"},
        {"fold_refinement",
         "how many times vfsd deform refines the mesh where triangles folded anyway and runs again; 0: never", "6"},
        {"steps", "fixed RK4 steps from t = 0 to 1, where tolerance is 0", "250"},
        {"tolerance",
         "error-controlled steps: each step's estimated error at most this fraction of the bounding box diagonal; 0: "
         "the fixed steps",
         "0.0005 (0 when the file gives steps)"},
        {"smoothing_steps", "Laplacian smoothing steps on the gradient per integration step", "10"},
        {"target_time", "where vfsd deform stops, in [0, 1]", "1"},
        {"up", "the axis the editors and vfsd render show up: \"z\" or \"y\" (a Y-up mesh)", "\"z\""},
    };
    return keys;
}

}  // namespace vfsd
