#include "io/mesh_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <numeric>
#include <unordered_map>

#include "base/error.h"
#include "io/format_io.h"
#include "mesh/builtin_meshes.h"
#include "mesh/orientation.h"

namespace vfsd {
namespace {

// The lower-case extension without the dot ("PLY" -> "ply").
std::string extension_of(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    if (!ext.empty()) ext.erase(0, 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

// Exact position equality as a hash key; -0.0 and +0.0 are the same position.
struct PositionKey {
    std::array<double, 3> xyz;
    bool operator==(const PositionKey& o) const { return xyz == o.xyz; }
};

struct PositionHash {
    std::size_t operator()(const PositionKey& k) const {
        std::size_t h = 0;
        for (double d : k.xyz) h = h * 1000003u ^ std::hash<double>()(d);
        return h;
    }
};

[[noreturn]] void throw_os_error(const std::string& path, const char* what) {
    throw IoError(path + ": " + what + ": " + std::strerror(errno));
}

// Creates a new temporary file next to `target`; returns its descriptor and name.
int open_temporary(const std::filesystem::path& target, std::string& name) {
    static unsigned counter = 0;
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::filesystem::path temp = target;
        temp.replace_filename("." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        name = temp.string();
        const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) return fd;
        if (errno != EEXIST) throw_os_error(target.string(), "cannot create a temporary file");
    }
    throw IoError(target.string() + ": cannot create a temporary file");
}

void write_all(int fd, const std::string& bytes, const std::string& path) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw_os_error(path, "write failed");
        done += static_cast<std::size_t>(n);
    }
    if (::fsync(fd) != 0) throw_os_error(path, "fsync failed");
}

// Makes the rename durable; best effort (not every file system can sync a folder).
void sync_folder(const std::filesystem::path& target) {
    const std::filesystem::path folder = target.has_parent_path() ? target.parent_path() : std::filesystem::path(".");
    const int fd = ::open(folder.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return;
    ::fsync(fd);
    ::close(fd);
}

MeshFile builtin_mesh_file(const std::string& spec) {
    const std::string rest = spec.substr(std::strlen("builtin:"));
    const std::size_t colon = rest.find(':');
    int resolution = 0;
    if (colon != std::string::npos) {
        const std::string text = rest.substr(colon + 1);
        const auto r = std::from_chars(text.data(), text.data() + text.size(), resolution);
        if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size() || resolution < 0) {
            throw InputError(spec + ": resolution must be a non-negative integer, got '" + text + "'");
        }
    }
    MeshFile file = weld_mesh(make_builtin_mesh(rest.substr(0, colon), resolution), "builtin");
    return file;
}

}  // namespace

bool MeshFile::layout_is_identity() const {
    return file_to_mesh.size() == mesh.vertex_count() && file_triangles == mesh.triangles;
}

MeshFile weld_mesh(TriangleMesh file_mesh, const std::string& format) {
    MeshFile out;
    out.format = format;
    const std::size_t n = file_mesh.vertex_count();
    const bool scalar = file_mesh.has_scalar();
    out.file_to_mesh.resize(n);
    std::unordered_map<PositionKey, std::uint32_t, PositionHash> first;
    first.reserve(n);
    // Welded vertices are numbered by first appearance, so a file without repeats keeps its order.
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = file_mesh.positions[i];
        const PositionKey key{{p.x + 0.0, p.y + 0.0, p.z + 0.0}};
        const auto [it, inserted] = first.emplace(key, static_cast<std::uint32_t>(out.mesh.positions.size()));
        if (inserted) {
            out.mesh.positions.push_back(p);
            if (scalar) out.mesh.scalar.push_back(file_mesh.scalar[i]);
        }
        out.file_to_mesh[i] = it->second;
    }
    // Triangles with a repeated corner (in the file or after welding) carry no area: drop them.
    for (const Triangle& t : file_mesh.triangles) {
        const Triangle w(out.file_to_mesh[t[0]], out.file_to_mesh[t[1]], out.file_to_mesh[t[2]]);
        if (w[0] != w[1] && w[1] != w[2] && w[0] != w[2]) out.mesh.triangles.push_back(w);
    }
    out.turned_triangles = orient_consistently(out.mesh.triangles);
    out.file_triangles = std::move(file_mesh.triangles);
    return out;
}

std::string turned_triangles_warning(const MeshFile& file) {
    if (file.turned_triangles == 0) return "";
    return "mesh: " + std::to_string(file.turned_triangles) + " of " + std::to_string(file.mesh.triangle_count()) +
           " triangles were wound against their neighbours; they are turned to agree (a result written in the "
           "file's layout keeps the file's triangles)";
}

namespace {

std::string lower(std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return text;
}

bool known_format(const std::string& ext) {
    return ext == "obj" || ext == "off" || ext == "ply" || ext == "stl" || ext == "gltf" || ext == "glb";
}

MeshFile read_known_format(const std::string& bytes, const std::string& ext, const std::string& name, bool external_files) {
    if (bytes.empty()) throw InputError(name + ": empty file");
    TriangleMesh mesh;
    if (ext == "obj") mesh = io::read_obj(name, bytes);
    else if (ext == "off") mesh = io::read_off(name, bytes);
    else if (ext == "ply") mesh = io::read_ply(name, bytes);
    else if (ext == "stl") mesh = io::read_stl(name, bytes);
    else mesh = io::read_gltf(name, bytes, ext == "glb", external_files);
    return weld_mesh(std::move(mesh), ext);
}

}  // namespace

MeshFile read_mesh_file(const std::string& path) {
    const std::string ext = extension_of(path);
    if (!known_format(ext)) throw InputError(path + ": unknown mesh format '." + ext + "' (expected .obj .off .ply .stl .gltf .glb)");
    return read_known_format(io::read_file_bytes(path), ext, path, true);
}

MeshFile read_mesh_bytes(const std::string& bytes, const std::string& format, const std::string& name) {
    const std::string ext = lower(format);
    if (!known_format(ext)) throw InputError(name + ": unknown mesh format '" + format + "' (expected obj off ply stl gltf glb)");
    return read_known_format(bytes, ext, name, false);
}

MeshFile load_mesh_file(const std::string& spec) {
    if (spec.rfind("builtin:", 0) == 0) return builtin_mesh_file(spec);
    return read_mesh_file(spec);
}

TriangleMesh load_mesh(const std::string& spec) { return load_mesh_file(spec).mesh; }

void write_mesh_file(const std::string& path, const TriangleMesh& mesh, const WriteOptions& options) {
    const std::string ext = extension_of(path);
    if (ext != "obj" && ext != "off" && ext != "ply" && ext != "glb") {
        throw InputError(path + ": cannot write '." + ext + "' files (write .obj .off .ply .glb)");
    }
    io::check_mesh(path, mesh);  // also refuses a mesh without triangles
    std::string bytes;
    if (ext == "obj") bytes = io::write_obj(mesh);
    else if (ext == "off") bytes = io::write_off(mesh);
    else if (ext == "ply") bytes = io::write_ply(mesh, options);
    else bytes = io::write_glb(mesh, options);
    write_file_atomically(path, bytes);
}

TriangleMesh to_file_layout(const MeshFile& file, const TriangleMesh& welded) {
    if (welded.vertex_count() != file.mesh.vertex_count()) {
        throw InputError("mesh has " + std::to_string(welded.vertex_count()) + " vertices, the file's layout expects " +
                         std::to_string(file.mesh.vertex_count()));
    }
    TriangleMesh out;
    out.triangles = file.file_triangles;
    out.positions.reserve(file.file_vertex_count());
    for (std::uint32_t w : file.file_to_mesh) out.positions.push_back(welded.positions[w]);
    if (welded.has_scalar()) {
        for (std::uint32_t w : file.file_to_mesh) out.scalar.push_back(welded.scalar[w]);
    }
    return out;
}

void write_file_atomically(const std::string& path, const std::string& bytes) {
    const std::filesystem::path target(path);
    std::string temp;
    const int fd = open_temporary(target, temp);
    bool open = true;
    try {
        write_all(fd, bytes, path);
        open = false;
        if (::close(fd) != 0) throw_os_error(path, "close failed");
    } catch (...) {
        if (open) ::close(fd);
        ::unlink(temp.c_str());
        throw;
    }
    if (std::rename(temp.c_str(), path.c_str()) != 0) {
        const int saved = errno;
        ::unlink(temp.c_str());
        errno = saved;
        throw_os_error(path, "cannot replace the file");
    }
    sync_folder(target);
}

}  // namespace vfsd
