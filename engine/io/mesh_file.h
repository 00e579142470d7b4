#pragma once
// Mesh files: the one entry point through which vfsd reads and writes meshes.
//
// Read:  .obj .off .ply (ascii, binary little- and big-endian) .stl (ascii, binary)
//        .gltf .glb (glTF 2.0, every triangle primitive of the default scene with
//        its node transforms applied).
// Write: .obj .off .ply (binary little-endian) .glb.
//
// Welding and the file layout
// ---------------------------
// Some formats split a vertex into several copies (STL stores three corners per
// triangle, glTF splits at UV/normal seams, OBJ exporters repeat positions). The
// deformation needs connectivity, so every file is welded on reading: vertices with
// exactly the same position become one. Welded vertices are numbered in order of
// first appearance in the file, so a file without repeated positions keeps its
// vertex indices unchanged. Triangles that welding (or the file) makes degenerate
// (a repeated corner) are dropped from the welded mesh, and triangles wound
// against their neighbours are turned to agree (mesh/orientation.h; the welded
// mesh only: a result written in the file's layout keeps the file's triangles).
//
// MeshFile keeps what is needed to write a result back in the file's own layout:
// `file_to_mesh[i]` is the welded vertex of file vertex i, and `file_triangles` are
// the file's triangles in file vertex indices. to_file_layout() scatters the welded
// positions (and scalar) back to file vertex order.
//
// Errors
// ------
// A malformed file throws vfsd::InputError with one line, "FILE:LINE: what" for
// text formats and "FILE: what" for binary ones; an operating-system failure throws
// vfsd::IoError. Writing is atomic: the bytes go to a temporary file in the target's
// folder, which is flushed to disk and then renamed over the target, so a failed or
// interrupted write never leaves a partial file.

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/triangle_mesh.h"

namespace vfsd {

struct MeshFile {
    TriangleMesh mesh;                        // welded: the mesh every algorithm uses
    std::vector<std::uint32_t> file_to_mesh;  // file vertex index -> welded vertex index
    std::vector<Triangle> file_triangles;     // the file's triangles, in file vertex indices
    std::string format;                       // "obj", "off", "ply", "stl", "gltf", "glb", "builtin"
    // Triangles of mesh turned to their neighbours' winding (mesh/orientation.h);
    // file_triangles keep the file's.
    std::size_t turned_triangles = 0;

    std::size_t file_vertex_count() const { return file_to_mesh.size(); }
    // True when the welded mesh is the file's mesh unchanged (same vertices, same triangles).
    bool layout_is_identity() const;
};

struct WriteOptions {
    bool double_positions = false;  // PLY: store positions as float64 instead of float32
    bool write_scalar = true;       // PLY: property "quality"; GLB: attribute "_SCALAR"
};

// Reads a mesh file, choosing the format by the (case-insensitive) extension.
MeshFile read_mesh_file(const std::string& path);

// Reads a mesh from `bytes` in memory. `format` is an extension without the dot
// ("obj", "off", "ply", "stl", "gltf", "glb", any case); `name` stands for the file
// in messages. A .gltf read from memory cannot load external buffer files (its
// buffers must be embedded data: URIs); otherwise the same as read_mesh_file.
MeshFile read_mesh_bytes(const std::string& bytes, const std::string& format, const std::string& name = "<memory>");

// `spec` is a file path or builtin:NAME[:RESOLUTION] (see mesh/builtin_meshes.h).
MeshFile load_mesh_file(const std::string& spec);
TriangleMesh load_mesh(const std::string& spec);

// Writes `mesh` atomically, the format chosen by the extension (.obj .off .ply .glb).
void write_mesh_file(const std::string& path, const TriangleMesh& mesh, const WriteOptions& options = {});

// The mesh in `file`'s original vertex layout, with the positions (and scalar, when
// present) of `welded` (a mesh with file.mesh's vertices, e.g. after deformation).
TriangleMesh to_file_layout(const MeshFile& file, const TriangleMesh& welded);

// Welds vertices with exactly equal positions (see above). `file_mesh` is the mesh
// as stored in a file; `source` names it in messages.
MeshFile weld_mesh(TriangleMesh file_mesh, const std::string& format);

// What a user should be told when welding turned triangles to their neighbours'
// winding ("" when it turned none).
std::string turned_triangles_warning(const MeshFile& file);

// Writes `bytes` to `path` through a temporary file in the same folder, fsync and
// rename. Throws IoError on failure, leaving any existing `path` untouched.
void write_file_atomically(const std::string& path, const std::string& bytes);

}  // namespace vfsd
