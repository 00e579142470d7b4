#pragma once
// Scene files: one JSON document says which mesh, which region, which curve (or
// handle), which inner motion and twist, and how many steps. The CLI, the editors
// and the tests all read the same format; docs/scene-format.md describes it.
//
// { "mesh": "path relative to the scene file, or builtin:NAME[:RESOLUTION]",
//   "region": {"kind": "painted", "inner": [SEL...], "outer": [SEL...]}
//           | {"kind": "geodesic", "seed": [x,y,z], "g_min": a, "g_max": b}
//           | {"kind": "implicit", "center": [x,y,z], "r_inner": a, "r_outer": b}
//           | {"kind": "field", "s": [one value per vertex]},
//   "curve": {"bezier": [[x,y,z], ...]}
//          | {"handle": {"from": {"position": P, "normal": M, "binormal": W}, "to": {...}}},
//   "inner_motion": "rotation" | "translation",
//   "twist_degrees": [a0, a1],
//   "twist_plane": "region" | "curve" | ζ0,          // where eq. (14)'s ẽ = 0 (default "region")
//   "stream_origin": "curve" | [x,y,z],               // where e, f are built about (default c(t))
//   "steps": 250, "smoothing_steps": 10, "target_time": 1.0,
//   "stream_gauge": "fit" | "paper",                  // beyond the paper (docs/method.md): defaults
//   "smoothing": "space" | "tangent",                 //   fit, space, true, true; "paper",
//   "keep_volume": true | false,                      //   "tangent", false, false is sec. 5
//   "fold_repair": true | false,                      //   as printed
//   "fold_refinement": 6 }                            // runs again refined where folded (scene/scene_run.h)

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "deform/deformation.h"
#include "region/geodesic.h"
#include "region/selectors.h"
#include "scene/motion_spec.h"

namespace vfsd {

struct RegionSpec {
    enum class Kind { painted, geodesic, implicit, field };
    // How s runs across the blend region of a painted or geodesic region: the
    // harmonic interpolation between the inner and outer regions (smooth, the
    // default: region/harmonic_blend.h) or eqs. (15)–(16) as printed (geodesic
    // distances, with their kinks).
    enum class Profile { harmonic, geodesic };
    Kind kind = Kind::painted;
    Profile profile = Profile::harmonic;
    std::vector<Selector> inner, outer;  // painted (eq. 16)
    double band = 0.0;                   // painted: the transition band where inner and outer meet
    Vec3 seed{0.0};                      // geodesic (eq. 15): nearest vertex to this point
    double g_min = 0.0, g_max = 0.0;
    GeodesicOptions geodesic;            // painted and geodesic
    SphereTool sphere;                   // implicit tool of [23]
    std::vector<double> s;               // field: given per vertex
};

// The tolerance of a scene file that gives neither "tolerance" nor "steps"
// (DeformationOptions::tolerance, relative to the diagonal).
constexpr double kSceneTolerance = 5e-4;

struct Scene {
    std::string mesh;  // a path (resolved against the scene's folder) or builtin:NAME
    RegionSpec region;
    MotionSpec motion;  // "curve", "inner_motion", "twist_degrees", "twist_plane", "stream_origin"
    DeformationOptions options;
    double target_time = 1.0;
    // The axis the editors and `vfsd render` show up: 'z' or 'y' (a Y-up mesh).
    char up_axis = 'z';
};

// Throws InputError naming the offending field ("scene.json: region.g_max: ...").
Scene parse_scene(const nlohmann::json& json, const std::string& base_dir, const std::string& name = "scene");
Scene load_scene(const std::string& path);
// The JSON document of a scene file's text: throws InputError "NAME: not valid JSON
// (...)" on a syntax error, and when arrays and objects nest deeper than
// kMaxSceneJsonDepth (a scene needs 5 levels; the limit keeps hostile files from
// exhausting memory or the stack).
constexpr int kMaxSceneJsonDepth = 64;
nlohmann::json parse_scene_json(const std::string& text, const std::string& name = "scene");
// The scene as JSON, with the mesh path as stored (parse_scene(to_json(s)) == s).
nlohmann::json scene_to_json(const Scene& scene);

// The keys of a scene file's top level, for listings (`vfsd scene-keys`); the
// table of docs/scene-format.md has a row for each (a test holds them equal).
struct SceneKey {
    const char* name;
    const char* value;          // what it takes
    const char* default_value;  // "required" when it has none
};
const std::vector<SceneKey>& scene_keys();

}  // namespace vfsd
