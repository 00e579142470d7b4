// Hostile and degenerate scenes (docs/robustness.md): JSON nested without end or
// very large, an empty inner region, s = 1 everywhere, a curve that starts outside
// the inner region, has zero length, is straight in rotation mode or has a cusp,
// a twist of ten full turns, target times outside [0, 1], and integrations that
// become non-finite. Each ends in a correct result (with a warning where the user
// should know) or in one clear error; the CLI then writes no output file.
#include <sys/wait.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "base/error.h"
#include "base/rigid_fit.h"
#include "deform/quality.h"
#include "io/mesh_file.h"
#include "mesh/builtin_meshes.h"
#include "scene/prepared_scene.h"
#include "test_io_support.h"

using namespace vfsd;
using nlohmann::json;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The box scene of fig. 4 on a coarse box: inner z > 0.3, outer z < -0.5.
json box_scene() {
    return {{"mesh", "builtin:box:6"},
            {"region", {{"kind", "painted"}, {"inner", {{{"halfspace", {0, 0, 1, 0.3}}}}}, {"outer", {{{"halfspace", {0, 0, -1, 0.5}}}}}}},
            {"curve", {{"bezier", {{0, 0, 0.6}, {0, 0, 1.0}, {0.3, 0, 1.4}, {0.8, 0, 1.6}}}}},
            {"steps", 40},
            {"smoothing_steps", 10}};
}

PreparedScene prepare(const json& j) { return prepare_scene(parse_scene(j, "", "hostile.json")); }

bool has_warning(const PreparedScene& p, const std::string& text) {
    for (const std::string& w : p.warnings)
        if (w.find(text) != std::string::npos) return true;
    return false;
}

// Runs the prepared scene to its target time; every position must be finite.
std::vector<Vec3> run(const PreparedScene& p) {
    Deformation d = p.start_deformation();
    d.advance(p.scene.target_time);
    for (const Vec3& x : d.positions()) REQUIRE(std::isfinite(x.x + x.y + x.z));
    return d.positions();
}

std::vector<Vec3> inner_of(const PreparedScene& p, const std::vector<Vec3>& x) {
    std::vector<Vec3> out;
    for (std::size_t v = 0; v < x.size(); ++v)
        if (p.region.s[v] == 0.0) out.push_back(x[v]);
    return out;
}

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("deeply nested JSON is refused at a fixed depth", "[hostile][scene]") {
    for (const std::string open : {"[", "{\"a\":"}) {
        std::string text;
        for (int i = 0; i < 200000; ++i) text += open;
        CHECK_THAT(message_of([&] { parse_scene_json(text, "deep.json"); }), Catch::Contains("deep.json: JSON nests deeper than 64"));
    }
    // 64 levels are fine (a scene needs 5).
    std::string ok(kMaxSceneJsonDepth - 1, '[');
    ok += std::string(kMaxSceneJsonDepth - 1, ']');
    CHECK_NOTHROW(parse_scene_json(ok));
    CHECK_THAT(message_of([&] { parse_scene_json("{\"mesh\": 1e999}", "big.json"); }), Catch::Contains("big.json: not valid JSON"));
}

TEST_CASE("huge scenes parse and are refused where they do not fit the mesh", "[hostile][scene]") {
    json j = box_scene();
    j["region"] = {{"kind", "field"}, {"s", std::vector<double>(300000, 0.5)}};
    const Scene scene = parse_scene(parse_scene_json(j.dump()), "", "huge.json");
    CHECK(scene.region.s.size() == 300000);
    CHECK_THAT(message_of([&] { prepare_scene(scene); }), Catch::Contains("300000 values for a mesh of"));
    // A curve of 10,000 segments is a valid curve.
    json curve = json::array();
    for (int i = 0; i <= 30000; ++i) curve.push_back({0.01 * std::sin(i * 0.001), 0.0, 0.6 + i * 1e-5});
    j = box_scene();
    j["curve"] = {{"bezier", curve}};
    j["steps"] = 4;
    CHECK_NOTHROW(run(prepare(j)));
}

TEST_CASE("an empty inner region and s = 1 everywhere move nothing, with a warning", "[hostile][scene]") {
    json j = box_scene();
    j["region"]["inner"] = {{{"sphere", {5, 5, 5, 0.1}}}};
    const PreparedScene empty = prepare(j);
    CHECK(has_warning(empty, "inner region is empty"));
    CHECK(run(empty) == empty.file.mesh.positions);

    j = box_scene();
    const std::size_t n = load_mesh("builtin:box:6").vertex_count();
    j["region"] = {{"kind", "field"}, {"s", std::vector<double>(n, 1.0)}};
    const PreparedScene ones = prepare(j);
    CHECK(has_warning(ones, "s is 1 everywhere"));
    CHECK(run(ones) == ones.file.mesh.positions);
}

TEST_CASE("a curve that does not start in the inner region warns and still deforms", "[hostile][scene]") {
    json j = box_scene();
    j["curve"]["bezier"] = {{0, 0, -0.6}, {0, 0, -1.0}, {0.3, 0, -1.4}, {0.8, 0, -1.6}};
    const PreparedScene p = prepare(j);
    CHECK(has_warning(p, "does not lie in the inner region"));
    run(p);
}

TEST_CASE("a zero-length curve warns and leaves the mesh where it is", "[hostile][scene]") {
    json j = box_scene();
    j["curve"]["bezier"] = {{0, 0, 0.6}, {0, 0, 0.6}, {0, 0, 0.6}, {0, 0, 0.6}};
    const PreparedScene p = prepare(j);
    CHECK(has_warning(p, "all control points coincide"));
    const std::vector<Vec3> after = run(p);
    for (std::size_t v = 0; v < after.size(); ++v) CHECK(glm::length(after[v] - p.file.mesh.positions[v]) < 1e-12);
}

TEST_CASE("a straight curve in rotation mode translates the inner region", "[hostile][scene]") {
    json j = box_scene();
    j["curve"]["bezier"] = {{0, 0, 0.6}, {0.1, 0, 0.7}, {0.2, 0, 0.8}, {0.3, 0, 0.9}};
    j["inner_motion"] = "rotation";
    const PreparedScene p = prepare(j);
    const std::vector<Vec3> after = run(p);
    const RigidFit fit = fit_rigid(inner_of(p, p.file.mesh.positions), inner_of(p, after));
    CHECK(rotation_angle(fit.rotation) < 1e-6);
    CHECK(glm::length(fit.apply(Vec3(0, 0, 0.6)) - Vec3(0.3, 0, 0.9)) < 1e-6);
}

TEST_CASE("a curve with a cusp deforms to its end without NaN", "[hostile][scene]") {
    // c'(0.5) = 0: the tangent reverses at the cusp.
    json j = box_scene();
    j["curve"]["bezier"] = {{0, 0, 0.6}, {0.3, 0, 0.9}, {0, 0, 0.9}, {0.3, 0, 0.6}};
    for (const char* mode : {"rotation", "translation"}) {
        j["inner_motion"] = mode;
        const PreparedScene p = prepare(j);
        const std::vector<Vec3> after = run(p);
        const RigidFit fit = fit_rigid(inner_of(p, p.file.mesh.positions), inner_of(p, after));
        INFO(mode);
        CHECK(glm::length(fit.apply(Vec3(0, 0, 0.6)) - Vec3(0.3, 0, 0.6)) < 1e-3);
    }
}

TEST_CASE("a twist of ten full turns is realised", "[hostile][scene]") {
    json j = box_scene();
    j["curve"]["bezier"] = {{0, 0, 0.6}, {0, 0, 0.7}, {0, 0, 0.8}, {0, 0, 0.9}};
    j["twist_degrees"] = {0, 3600};
    j["steps"] = 400;
    const PreparedScene p = prepare(j);
    Deformation d = p.start_deformation();
    double turned = 0.0;
    std::vector<Vec3> previous = inner_of(p, d.positions());
    for (int k = 1; k <= 100; ++k) {  // 36 degrees per interval: the sign of each turn is unambiguous
        d.advance(k / 100.0);
        const std::vector<Vec3> current = inner_of(p, d.positions());
        const glm::dmat3 r = fit_rigid(previous, current).rotation;
        turned += ((r[0][1] - r[1][0]) >= 0.0 ? 1.0 : -1.0) * rotation_angle(r);
        previous = current;
    }
    CHECK(std::abs(turned * 180.0 / kPi - 3600.0) < 1.0);
    const DeformationQuality q = measure_quality(p.file.mesh.positions, d.positions(), p.file.mesh.triangles, p.region.s);
    CHECK(q.nonfinite_vertices == 0);
    CHECK(q.outer_max_displacement == 0.0);
}

TEST_CASE("target times outside [0, 1] are refused", "[hostile][scene]") {
    for (double t : {-0.1, 1.5, 1e300}) {
        json j = box_scene();
        j["target_time"] = t;
        CHECK_THAT(message_of([&] { parse_scene(j, "", "t.json"); }), Catch::Contains("t.json: target_time: expected a time in [0, 1]"));
    }
}

TEST_CASE("a non-finite position during integration stops with the step and the vertex", "[hostile][scene]") {
    SECTION("a NaN position") {
        const TriangleMesh box = make_builtin_mesh("box", 2);
        std::vector<Vec3> x = box.positions;
        std::vector<double> s(x.size(), 0.5);
        x[3].y = std::numeric_limits<double>::quiet_NaN();
        Deformation d(x, build_vertex_rings(box), Region{s, {}},
                      InnerMotion::along_curve(BezierCurve({{0, 0, 0.6}, {0, 0, 1}, {0, 0, 1.4}, {0, 0, 1.8}}),
                                               InnerMotionMode::Translation, 0, 0));
        const std::string message = message_of([&] { d.advance(1.0); });
        CHECK_THAT(message, Catch::Contains("integration step 1") && Catch::Contains("vertex 3"));
        CHECK(d.time() == 0.0);  // the positions before the failed step are kept
    }
    SECTION("an enormous velocity") {
        json j = box_scene();
        j["curve"]["bezier"] = {{0, 0, 0.6}, {0, 0, 1e307}, {1e307, 0, 1e307}, {1e307, 1e307, 1e307}};
        j["inner_motion"] = "translation";
        const PreparedScene p = prepare(j);
        Deformation d = p.start_deformation();
        CHECK_THAT(message_of([&] { d.advance(1.0); }), Catch::Contains("integration step") && Catch::Contains("non-finite"));
    }
}

TEST_CASE("vfsd deform stops on a non-finite integration without writing the output", "[hostile][scene][cli]") {
    test::ScratchDir dir;
    json j = box_scene();
    j["curve"]["bezier"] = {{0, 0, 0.6}, {0, 0, 1e307}, {1e307, 0, 1e307}, {1e307, 1e307, 1e307}};
    j["inner_motion"] = "translation";
    test::write_bytes(dir.file("scene.json"), j.dump());
    const std::string command = std::string("'") + VFSD_CLI_PATH + "' deform '" + dir.file("scene.json") + "' --out '" +
                                dir.file("out.ply") + "' --report '" + dir.file("report.json") + "' 2>'" +
                                dir.file("stderr.txt") + "' >/dev/null";
    const int status = std::system(command.c_str());
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 1);
    CHECK_FALSE(std::filesystem::exists(dir.file("out.ply")));
    CHECK_FALSE(std::filesystem::exists(dir.file("report.json")));
    std::ifstream err(dir.file("stderr.txt"));
    const std::string text((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
    CHECK_THAT(text, Catch::Contains("integration step") && Catch::Contains("vertex"));
    for (const auto& entry : std::filesystem::directory_iterator(dir.file("")))  // no temporary file left behind
        CHECK(entry.path().filename().string().find(".tmp-") == std::string::npos);
}

TEST_CASE("the CLI report says when the volume is undefined", "[hostile][scene][cli]") {
    test::ScratchDir dir;
    TriangleMesh sheet;
    for (int j = 0; j <= 12; ++j)
        for (int i = 0; i <= 4; ++i) sheet.positions.push_back(Vec3(i / 4.0 - 0.5, 0.0, j / 10.0 - 0.6));
    for (std::uint32_t j = 0; j < 12; ++j)
        for (std::uint32_t i = 0; i < 4; ++i) {
            const std::uint32_t a = j * 5 + i;
            sheet.triangles.push_back({a, a + 1, a + 6});
            sheet.triangles.push_back({a, a + 6, a + 5});
        }
    write_mesh_file(dir.file("sheet.obj"), sheet);
    json j = box_scene();
    j["mesh"] = "sheet.obj";
    test::write_bytes(dir.file("scene.json"), j.dump());
    const std::string command = std::string("'") + VFSD_CLI_PATH + "' deform '" + dir.file("scene.json") + "' --out '" +
                                dir.file("out.obj") + "' --report '" + dir.file("report.json") + "' >'" +
                                dir.file("stdout.txt") + "' 2>&1";
    REQUIRE(std::system(command.c_str()) == 0);
    std::ifstream in(dir.file("report.json"));
    const json report = json::parse(in);
    CHECK(report["volume_defined"] == false);
    std::ifstream out(dir.file("stdout.txt"));
    const std::string text((std::istreambuf_iterator<char>(out)), std::istreambuf_iterator<char>());
    CHECK_THAT(text, Catch::Contains("volume undefined"));
}

TEST_CASE("stream_origin is \"curve\" or a point, and survives a save", "[hostile][scene]") {
    json j = box_scene();
    for (const json& bad : {json("region"), json({1, 2}), json(3.0), json({1, "a", 2})}) {
        j["stream_origin"] = bad;
        CHECK_THAT(message_of([&] { parse_scene(j, "", "o.json"); }), Catch::Contains("o.json: stream_origin: expected"));
    }
    j["stream_origin"] = "curve";
    CHECK_FALSE(parse_scene(j, "", "o.json").motion.stream_origin.has_value());
    j["stream_origin"] = {0.1, 0.2, -0.1};
    const Scene scene = parse_scene(j, "", "o.json");
    REQUIRE(scene.motion.stream_origin.has_value());
    CHECK(*scene.motion.stream_origin == Vec3(0.1, 0.2, -0.1));
    const Scene again = parse_scene(scene_to_json(scene), "", "o.json");
    REQUIRE(again.motion.stream_origin.has_value());
    CHECK(*again.motion.stream_origin == *scene.motion.stream_origin);
    CHECK(build_motion(again.motion).at(0.5).stream_origin == Vec3(0.1, 0.2, -0.1));
}

TEST_CASE("a scene's up axis is z unless it says y, survives a save, and a third axis is refused", "[hostile][scene]") {
    json j = box_scene();
    CHECK(parse_scene(j, "", "up.json").up_axis == 'z');
    j["up"] = "y";
    const Scene y_up = parse_scene(j, "", "up.json");
    CHECK(y_up.up_axis == 'y');
    CHECK(parse_scene(scene_to_json(y_up), "", "again.json").up_axis == 'y');
    for (const json& bad : {json("x"), json("Y"), json(1), json::array()}) {
        j["up"] = bad;
        CHECK_THROWS_WITH(parse_scene(j, "", "up.json"), Catch::Contains("up.json: up: expected \"z\" or \"y\""));
    }
}
