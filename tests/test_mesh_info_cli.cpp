// `vfsd info`: the --json report on built-in meshes and on a file.

#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "mesh_fixtures.h"

using nlohmann::json;

namespace {

// Runs the CLI; returns its exit status and fills `out` with its stdout.
int run_cli(const std::string& arguments, std::string& out) {
    const std::string command = std::string(VFSD_CLI_PATH) + " " + arguments + " 2>/dev/null";
    FILE* pipe = popen(command.c_str(), "r");
    REQUIRE(pipe != nullptr);
    out.clear();
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) out.append(buf, n);
    const int status = pclose(pipe);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

json info_json(const std::string& spec) {
    std::string out;
    REQUIRE(run_cli("info '" + spec + "' --json", out) == 0);
    return json::parse(out);
}

}  // namespace

TEST_CASE("vfsd info --json on a built-in mesh", "[mesh][cli]") {
    const json d = info_json("builtin:bar");
    CHECK(d["vertices"] == 9730);
    CHECK(d["triangles"] == 19456);
    CHECK(d["closed"] == true);
    CHECK(d["manifold"] == true);
    CHECK(d["boundary_loops"].empty());
    CHECK(d["signed_volume"].get<double>() == Approx(9.0));
    CHECK(d["bounding_box"]["extent"][2].get<double>() == Approx(9.0));
    CHECK(d["valence"]["min"] == 4);
    CHECK(d["valence"]["histogram"]["6"].get<std::size_t>() > 9000);

    std::string text;
    CHECK(run_cli("info builtin:sphere:2", text) == 0);
    CHECK(text.find("vertices       162") != std::string::npos);
    CHECK(text.find("manifold       yes") != std::string::npos);
}

TEST_CASE("vfsd info on an open mesh file", "[mesh][cli]") {
    // An OFF file of a 3 x 2 grid: open, one boundary loop of 10 edges.
    const vfsd::TriangleMesh g = vfsd::fixtures::grid(3, 2);
    const auto path = std::filesystem::temp_directory_path() / ("vfsd-info-grid-" + std::to_string(::getpid()) + ".off");
    {
        std::ofstream f(path);
        f << "OFF\n" << g.vertex_count() << " " << g.triangle_count() << " 0\n";
        for (const auto& p : g.positions) f << p.x << " " << p.y << " " << p.z << "\n";
        for (const auto& t : g.triangles) f << "3 " << t[0] << " " << t[1] << " " << t[2] << "\n";
    }
    const json d = info_json(path.string());
    std::filesystem::remove(path);
    CHECK(d["vertices"] == 12);
    CHECK(d["closed"] == false);
    CHECK(d["manifold"] == true);
    CHECK(d["boundary_loops"] == json::array({10}));
    CHECK(d["signed_volume"].is_null());
    CHECK(d["volume_note"] == "undefined: open mesh");
}

TEST_CASE("vfsd info on a file wound inconsistently says how many triangles it turned", "[mesh][cli]") {
    // The same grid with every third triangle wound the other way.
    const vfsd::TriangleMesh g = vfsd::fixtures::grid(3, 2);
    const auto path =
        std::filesystem::temp_directory_path() / ("vfsd-info-wound-" + std::to_string(::getpid()) + ".off");
    {
        std::ofstream f(path);
        f << "OFF\n" << g.vertex_count() << " " << g.triangle_count() << " 0\n";
        for (const auto& p : g.positions) f << p.x << " " << p.y << " " << p.z << "\n";
        for (std::size_t i = 0; i < g.triangles.size(); ++i) {
            const auto& t = g.triangles[i];
            f << "3 " << t[0] << " " << (i % 3 == 0 ? t[2] : t[1]) << " " << (i % 3 == 0 ? t[1] : t[2]) << "\n";
        }
    }
    const json d = info_json(path.string());
    std::string text;
    CHECK(run_cli("info '" + path.string() + "'", text) == 0);
    std::filesystem::remove(path);
    CHECK(d["turned_triangles"] == 4);  // 4 of 12 against the majority
    CHECK(d["manifold"] == true);       // once turned
    CHECK(text.find("winding        4 triangles turned") != std::string::npos);
}

TEST_CASE("vfsd info reports bad input and bad usage", "[mesh][cli]") {
    std::string out;
    CHECK(run_cli("info builtin:torus", out) == 1);
    CHECK(run_cli("info", out) == 2);
    CHECK(run_cli("info builtin:box --frobnicate", out) == 2);
}
