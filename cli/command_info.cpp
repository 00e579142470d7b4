// vfsd info MESH [--json]
//
// Reads MESH (a file or builtin:NAME[:RESOLUTION]) and prints its counts, topology
// (boundary loops, closed, manifold and why not), valence histogram, bounding box
// and signed volume; --json prints the same as one JSON object.

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "io/mesh_file.h"
#include "mesh/geometry.h"
#include "mesh/validation.h"

namespace vfsd::cli {
namespace {

using nlohmann::json;

json vec_json(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

// Everything `info` reports, as JSON; the text form is printed from it.
json describe_mesh(const std::string& spec, const MeshFile& file) {
    const TriangleMesh& mesh = file.mesh;
    const ValidationReport report = validate_mesh(mesh);
    const BoundingBox box = bounding_box(mesh.positions);

    json loops = json::array();
    for (const auto& loop : report.boundary_loops) loops.push_back(loop.size());
    json histogram = json::object();
    for (std::size_t k = 0; k < report.valence_histogram.size(); ++k)
        if (report.valence_histogram[k]) histogram[std::to_string(k)] = report.valence_histogram[k];

    json out;
    out["mesh"] = spec;
    out["format"] = file.format;
    out["file_vertices"] = file.file_vertex_count();
    out["turned_triangles"] = file.turned_triangles;
    out["vertices"] = mesh.vertex_count();
    out["triangles"] = mesh.triangle_count();
    out["boundary_edges"] = report.boundary_edges.size();
    out["boundary_loops"] = loops;
    out["closed"] = report.is_closed;
    out["manifold"] = report.is_manifold;
    out["reasons"] = report.reasons;
    out["warnings"] = report.warnings;
    out["problems"] = {{"non_manifold_edges", report.non_manifold_edges.size()},
                       {"non_manifold_vertices", report.non_manifold_vertices.size()},
                       {"degenerate_triangles", report.degenerate_triangles.size()},
                       {"duplicate_triangles", report.duplicate_triangles.size()},
                       {"isolated_vertices", report.isolated_vertices.size()},
                       {"non_finite_vertices", report.non_finite_vertices.size()},
                       {"out_of_range_triangles", report.out_of_range_triangles.size()}};
    out["valence"] = {{"min", report.valence_min}, {"max", report.valence_max}, {"histogram", histogram}};
    out["bounding_box"] = {{"min", vec_json(box.min)}, {"max", vec_json(box.max)}, {"extent", vec_json(box.extent())}};
    out["diagonal"] = box.diagonal();
    // Sec. 7.2's volume is the enclosed volume only for a closed mesh.
    if (report.is_closed) {
        out["signed_volume"] = signed_volume(mesh.positions, mesh.triangles);
        out["volume_note"] = report.is_manifold ? "" : "non-manifold mesh: sum over all triangles";
    } else {
        out["signed_volume"] = nullptr;
        out["volume_note"] = "undefined: open mesh";
    }
    return out;
}

std::string join(const json& items, const char* separator) {
    std::string s;
    for (const auto& item : items) s += (s.empty() ? "" : separator) + item.get<std::string>();
    return s;
}

std::string vec_text(const json& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.6g, %.6g, %.6g)", v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    return buf;
}

void print_text(const json& d) {
    std::printf("mesh           %s (%s)\n", d["mesh"].get<std::string>().c_str(), d["format"].get<std::string>().c_str());
    std::printf("vertices       %zu", d["vertices"].get<std::size_t>());
    if (d["file_vertices"] != d["vertices"]) std::printf(" (welded from %zu in the file)", d["file_vertices"].get<std::size_t>());
    std::printf("\ntriangles      %zu\n", d["triangles"].get<std::size_t>());
    std::string loops;
    for (const auto& n : d["boundary_loops"]) loops += (loops.empty() ? "" : ", ") + std::to_string(n.get<std::size_t>());
    std::printf("boundary loops %zu%s\n", d["boundary_loops"].size(), loops.empty() ? "" : (" (edges: " + loops + ")").c_str());
    std::printf("closed         %s\n", d["closed"].get<bool>() ? "yes" : "no");
    std::printf("manifold       %s\n", d["manifold"].get<bool>() ? "yes" : ("no: " + join(d["reasons"], "; ")).c_str());
    if (d["turned_triangles"].get<std::size_t>() > 0)
        std::printf(
            "winding        %zu triangles turned to agree with their neighbours (the file's were wound "
            "against them)\n",
            d["turned_triangles"].get<std::size_t>());
    if (!d["warnings"].empty()) std::printf("warnings       %s\n", join(d["warnings"], "; ").c_str());
    std::printf("valence        min %u, max %u; histogram", d["valence"]["min"].get<unsigned>(), d["valence"]["max"].get<unsigned>());
    // JSON object keys sort as text ("10" < "3"): print in numeric order.
    std::vector<std::pair<unsigned long, std::size_t>> bins;
    for (const auto& [k, n] : d["valence"]["histogram"].items()) bins.push_back({std::stoul(k), n.get<std::size_t>()});
    std::sort(bins.begin(), bins.end());
    for (const auto& [k, n] : bins) std::printf(" %lu:%zu", k, n);
    std::printf("\nbounding box   min %s max %s\n", vec_text(d["bounding_box"]["min"]).c_str(), vec_text(d["bounding_box"]["max"]).c_str());
    std::printf("extent         %s\n", vec_text(d["bounding_box"]["extent"]).c_str());
    std::printf("diagonal       %.6g\n", d["diagonal"].get<double>());
    if (d["signed_volume"].is_null()) {
        std::printf("signed volume  %s\n", d["volume_note"].get<std::string>().c_str());
    } else {
        const std::string note = d["volume_note"];
        std::printf("signed volume  %.9g%s\n", d["signed_volume"].get<double>(), note.empty() ? "" : (" (" + note + ")").c_str());
    }
}

}  // namespace

int run_info(const Args& args) {
    // A flag followed by a word parses as "--json WORD": that word is the mesh.
    const std::string flag_value = args.get("json");
    args.expect({"json"}, flag_value.empty() ? 1 : 0, flag_value.empty() ? 1 : 0);
    const std::string spec = flag_value.empty() ? args.positional(0, "mesh") : flag_value;
    const json d = describe_mesh(spec, load_mesh_file(spec));
    if (args.has("json"))
        std::printf("%s\n", d.dump(2).c_str());
    else
        print_text(d);
    return kExitOk;
}

}  // namespace vfsd::cli
