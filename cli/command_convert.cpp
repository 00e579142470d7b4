// vfsd convert IN OUT [--force] [--keep-layout] [--double] [--subdivide N]
//
// Reads IN (a mesh file or builtin:NAME[:RESOLUTION]), welds it, and writes OUT
// atomically. --keep-layout writes the file's own vertex layout instead of the
// welded mesh (e.g. STL's three vertices per triangle); --double stores PLY
// positions as float64; --subdivide N splits every triangle into four at its
// edge midpoints N times (mesh/subdivision.h).

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "base/error.h"
#include "cli/commands.h"
#include "io/mesh_file.h"
#include "mesh/subdivision.h"

namespace vfsd::cli {
namespace {

// Refuses to overwrite the input, or an existing output without --force.
void check_output(const std::string& in, const std::string& out, bool force) {
    std::error_code ec;
    if (!std::filesystem::exists(out, ec)) return;
    if (std::filesystem::exists(in, ec) && std::filesystem::equivalent(in, out, ec)) {
        throw vfsd::InputError(out + ": is the same file as the input; write to another file");
    }
    if (std::filesystem::is_directory(out, ec)) throw vfsd::InputError(out + ": is a directory");
    if (!force) throw vfsd::InputError(out + ": already exists (pass --force to replace it)");
}

}  // namespace

int run_convert(const Args& args) {
    args.expect({"force", "keep-layout", "double", "subdivide"}, 2, 2);
    const double levels = args.get_number("subdivide", 0.0);
    if (levels < 0.0 || levels > 6.0 || levels != static_cast<int>(levels))
        throw UsageError("--subdivide expects a whole number from 0 to 6");
    if (levels > 0.0 && args.has("keep-layout")) throw UsageError("--subdivide and --keep-layout exclude each other");
    const std::string& in = args.positional(0, "input mesh");
    const std::string& out = args.positional(1, "output file");
    check_output(in, out, args.has("force"));
    const MeshFile file = load_mesh_file(in);
    WriteOptions options;
    options.double_positions = args.has("double");
    TriangleMesh mesh = args.has("keep-layout") ? to_file_layout(file, file.mesh) : file.mesh;
    for (int level = 0; level < static_cast<int>(levels); ++level) mesh = subdivide_midpoints(mesh);
    write_mesh_file(out, mesh, options);
    std::printf("%s: %zu vertices, %zu triangles (%zu vertices in %s)\n", out.c_str(), mesh.vertex_count(),
                mesh.triangle_count(), file.file_vertex_count(), in.c_str());
    return kExitOk;
}

}  // namespace vfsd::cli
