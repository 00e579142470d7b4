#include "scene/scene_package.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "io/format_io.h"
#include "io/mesh_file.h"

namespace vfsd {
namespace {

bool is_builtin(const std::string& mesh) { return mesh.rfind("builtin:", 0) == 0; }

// A copy of the file alone holds the whole mesh (a .gltf's buffers may be other files).
bool copyable(const std::string& mesh) {
    std::string ext = std::filesystem::path(mesh).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext != ".gltf";
}

// `copy` holds the bytes of `source` already: the same file, or a copy written
// after the source's last change.
bool copy_is_current(const std::filesystem::path& source, const std::filesystem::path& copy) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::exists(copy, ec)) return false;
    if (fs::equivalent(source, copy, ec)) return true;
    return fs::file_size(source, ec) == fs::file_size(copy, ec) && !ec &&
           fs::last_write_time(copy, ec) >= fs::last_write_time(source, ec) && !ec;
}

// Copies the mesh file `source` beside the scene file `scene_path` as
// SCENE.input.EXT (unless the copy is current); returns that name.
std::string copy_beside(const std::string& source, const std::string& scene_path) {
    namespace fs = std::filesystem;
    const fs::path scene(scene_path);
    const std::string name = scene.stem().string() + ".input" + fs::path(source).extension().string();
    const fs::path copy = fs::absolute(scene).parent_path() / name;
    if (!copy_is_current(source, copy)) write_file_atomically(copy.string(), io::read_file_bytes(source));
    return name;
}

}  // namespace

void write_scene_package(const std::string& path, Scene scene, InputMesh input, const TriangleMesh* baked) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::absolute(path).parent_path();
    if (baked) {
        // The applied (baked) mesh exists only here: write it beside the scene.
        const std::string name = fs::path(path).stem().string() + ".mesh.ply";
        WriteOptions options;
        options.double_positions = true;
        options.write_scalar = false;
        write_mesh_file((dir / name).string(), *baked, options);
        scene.mesh = name;
    } else if (!is_builtin(scene.mesh) && input == InputMesh::copied && copyable(scene.mesh)) {
        scene.mesh = copy_beside(scene.mesh, path);
    } else if (!is_builtin(scene.mesh)) {
        scene.mesh = fs::proximate(fs::absolute(scene.mesh), dir).string();
    }
    write_file_atomically(path, scene_to_json(scene).dump(2) + "\n");
}

}  // namespace vfsd
