// glTF 2.0 (.gltf with its buffers, or .glb) through tinygltf. Every primitive of
// mode TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN reachable from the default scene
// (all scenes when none is the default) is read with its node's world transform
// applied; a transform with negative determinant flips the winding (glTF 2.0,
// sec. 3.7.4). File vertices are the primitives' vertices, concatenated in
// traversal order. The optional vertex attribute "_SCALAR" (float) is the
// per-vertex scalar. Written as GLB: one node, one mesh, one primitive.

#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "base/error.h"
#include "io/format_io.h"
#include "io/tinygltf.h"

namespace vfsd::io {
namespace {

using Mat4 = glm::dmat4;

constexpr int kTriangles = 4, kTriangleStrip = 5, kTriangleFan = 6;

struct GltfReader {
    const std::string& path;
    const tinygltf::Model& model;
    TriangleMesh mesh;
    bool all_have_scalar = true;

    [[noreturn]] void fail(const std::string& what) const { throw InputError(path + ": " + what); }
};

// A bounds-checked view of an accessor's elements.
struct AccessorView {
    const unsigned char* first = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
    int component_type = 0;
};

AccessorView view_accessor(const GltfReader& r, int index, int type, const char* what) {
    const auto& m = r.model;
    if (index < 0 || static_cast<std::size_t>(index) >= m.accessors.size()) r.fail(std::string(what) + " accessor index out of range");
    const tinygltf::Accessor& a = m.accessors[index];
    if (a.type != type) r.fail(std::string(what) + " accessor has the wrong type");
    if (a.sparse.isSparse) r.fail(std::string(what) + " accessor is sparse (not supported)");
    if (a.bufferView < 0 || static_cast<std::size_t>(a.bufferView) >= m.bufferViews.size()) r.fail(std::string(what) + " accessor has no valid buffer view");
    const tinygltf::BufferView& bv = m.bufferViews[a.bufferView];
    if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= m.buffers.size()) r.fail(std::string(what) + " buffer view has no valid buffer");
    const std::vector<unsigned char>& data = m.buffers[bv.buffer].data;
    const int component = tinygltf::GetComponentSizeInBytes(a.componentType);
    if (component <= 0) r.fail(std::string(what) + " accessor has an invalid component type");
    const std::size_t element = static_cast<std::size_t>(component) * tinygltf::GetNumComponentsInType(a.type);
    const std::size_t stride = bv.byteStride ? bv.byteStride : element;
    // The elements must lie inside the buffer view, and the view inside the buffer.
    const bool view_ok = bv.byteOffset <= data.size() && bv.byteLength <= data.size() - bv.byteOffset;
    const bool fits = a.count == 0 || (a.byteOffset <= bv.byteLength && element <= bv.byteLength - a.byteOffset &&
                                       (a.count - 1) <= (bv.byteLength - a.byteOffset - element) / stride);
    if (!view_ok || !fits || stride < element) r.fail(std::string(what) + " accessor reaches beyond its buffer");
    return {data.data() + bv.byteOffset + a.byteOffset, stride, a.count, a.componentType};
}

std::uint32_t index_at(const AccessorView& v, std::size_t i) {
    const unsigned char* p = v.first + i * v.stride;
    if (v.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return *p;
    if (v.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
        std::uint16_t x;
        std::memcpy(&x, p, 2);
        return x;
    }
    std::uint32_t x;
    std::memcpy(&x, p, 4);
    return x;
}

float float_at(const AccessorView& v, std::size_t i, int k) {
    float x;
    std::memcpy(&x, v.first + i * v.stride + 4 * k, 4);
    return x;
}

// The primitive's corner list: its indices, or 0..n-1 when it has none.
std::vector<std::uint32_t> primitive_indices(const GltfReader& r, const tinygltf::Primitive& prim, std::size_t vertex_count) {
    std::vector<std::uint32_t> corners;
    if (prim.indices < 0) {
        for (std::size_t i = 0; i < vertex_count; ++i) corners.push_back(static_cast<std::uint32_t>(i));
        return corners;
    }
    const AccessorView v = view_accessor(r, prim.indices, TINYGLTF_TYPE_SCALAR, "index");
    const int t = v.component_type;
    if (t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        r.fail("index accessor must be of unsigned integers");
    }
    for (std::size_t i = 0; i < v.count; ++i) {
        corners.push_back(index_at(v, i));
        if (corners.back() >= vertex_count) r.fail("index " + std::to_string(corners.back()) + " is out of range (" + std::to_string(vertex_count) + " vertices)");
    }
    return corners;
}

// Triangles of a TRIANGLES / TRIANGLE_STRIP / TRIANGLE_FAN corner list (glTF 2.0, sec. 3.7.2.1).
void append_primitive_triangles(TriangleMesh& mesh, int mode, const std::vector<std::uint32_t>& c, std::uint32_t base, bool flip) {
    auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t d) {
        if (flip) std::swap(b, d);
        mesh.triangles.push_back({base + a, base + b, base + d});
    };
    if (mode == kTriangles) {
        for (std::size_t i = 0; i + 2 < c.size(); i += 3) add(c[i], c[i + 1], c[i + 2]);
    } else if (mode == kTriangleStrip) {
        for (std::size_t i = 0; i + 2 < c.size(); ++i) add(c[i], c[i + 1 + i % 2], c[i + 2 - i % 2]);
    } else {
        for (std::size_t i = 1; i + 1 < c.size(); ++i) add(c[i], c[i + 1], c[0]);
    }
}

void add_primitive(GltfReader& r, const tinygltf::Primitive& prim, const Mat4& world) {
    const int mode = prim.mode < 0 ? kTriangles : prim.mode;
    if (mode != kTriangles && mode != kTriangleStrip && mode != kTriangleFan) return;  // points and lines
    const auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end()) r.fail("triangle primitive without POSITION");
    const AccessorView p = view_accessor(r, position->second, TINYGLTF_TYPE_VEC3, "POSITION");
    if (p.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT) r.fail("POSITION must be float");
    const auto base = static_cast<std::uint32_t>(r.mesh.positions.size());
    for (std::size_t i = 0; i < p.count; ++i) {
        const glm::dvec4 local(float_at(p, i, 0), float_at(p, i, 1), float_at(p, i, 2), 1.0);
        r.mesh.positions.push_back(Vec3(world * local));
    }
    const auto scalar = prim.attributes.find("_SCALAR");
    if (scalar != prim.attributes.end() && r.all_have_scalar) {
        const AccessorView s = view_accessor(r, scalar->second, TINYGLTF_TYPE_SCALAR, "_SCALAR");
        if (s.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT || s.count != p.count) r.fail("_SCALAR must be float, one per vertex");
        for (std::size_t i = 0; i < s.count; ++i) r.mesh.scalar.push_back(float_at(s, i, 0));
    } else {
        r.all_have_scalar = false;
    }
    const bool flip = glm::determinant(world) < 0.0;
    append_primitive_triangles(r.mesh, mode, primitive_indices(r, prim, p.count), base, flip);
}

Mat4 local_matrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());  // column-major in glTF and glm
    Mat4 m(1.0);
    if (node.translation.size() == 3) m = glm::translate(m, Vec3(node.translation[0], node.translation[1], node.translation[2]));
    if (node.rotation.size() == 4) {
        m = m * glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
    }
    if (node.scale.size() == 3) m = glm::scale(m, Vec3(node.scale[0], node.scale[1], node.scale[2]));
    return m;
}

void add_mesh(GltfReader& r, int mesh_index, const Mat4& world) {
    if (mesh_index < 0) return;
    if (static_cast<std::size_t>(mesh_index) >= r.model.meshes.size()) r.fail("node refers to a missing mesh");
    for (const tinygltf::Primitive& prim : r.model.meshes[mesh_index].primitives) add_primitive(r, prim, world);
}

// Depth-first over the node tree below `roots`, without recursion (file-controlled depth).
void add_scene_nodes(GltfReader& r, const std::vector<int>& roots) {
    std::vector<std::pair<int, Mat4>> stack;
    std::vector<char> seen(r.model.nodes.size(), 0);
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, Mat4(1.0));
    while (!stack.empty()) {
        const auto [index, parent] = stack.back();
        stack.pop_back();
        if (index < 0 || static_cast<std::size_t>(index) >= r.model.nodes.size()) r.fail("node index " + std::to_string(index) + " out of range");
        if (seen[index]) r.fail("node " + std::to_string(index) + " is reached twice (the node graph is not a tree)");
        seen[index] = 1;
        const tinygltf::Node& node = r.model.nodes[index];
        const Mat4 world = parent * local_matrix(node);
        add_mesh(r, node.mesh, world);
        for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.emplace_back(*c, world);
    }
}

bool ignore_image(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) { return true; }

// tinygltf reports several lines; vfsd errors are one line.
std::string one_line(std::string text) {
    while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
    for (char& ch : text) ch = ch == '\n' ? ';' : ch;
    return text;
}

// File callbacks for a file read from memory: there is no folder to load external buffers from.
bool no_file_exists(const std::string&, void*) { return false; }
std::string no_expand(const std::string& path, void*) { return path; }
bool no_read(std::vector<unsigned char>*, std::string* err, const std::string& path, void*) {
    if (err) *err += "external file '" + path + "' cannot be loaded when reading from memory";
    return false;
}
bool no_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "writing is not supported";
    return false;
}

tinygltf::Model load_model(const std::string& path, const std::string& bytes, bool binary, bool external_files) {
    if (bytes.empty()) throw InputError(path + ": empty file");
    if (bytes.size() > 0xffffffffu) throw InputError(path + ": file too large for glTF");
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(ignore_image, nullptr);
    if (!external_files) loader.SetFsCallbacks({no_file_exists, no_expand, no_read, no_write, nullptr});
    tinygltf::Model model;
    std::string err, warn;
    const std::string dir = external_files ? std::filesystem::path(path).parent_path().string() : std::string();  // external buffers are relative to it
    const auto size = static_cast<unsigned int>(bytes.size());
    const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()), size, dir)
                           : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), size, dir);
    if (!ok) throw InputError(path + ": " + (err.empty() ? std::string("not a valid glTF file") : one_line(err)));
    return model;
}

// The glTF JSON of a GLB whose binary chunk holds positions, indices and (optionally) the scalar.
nlohmann::json glb_json(const TriangleMesh& mesh, bool scalar, std::size_t binary_bytes) {
    using nlohmann::json;
    const std::size_t nv = mesh.vertex_count(), nt = mesh.triangle_count();
    // min and max must be those of the stored float values.
    const auto stored = [](const Vec3& p) { return Vec3(glm::vec3(p)); };
    BoundingBox box{stored(mesh.positions[0]), stored(mesh.positions[0])};
    for (const Vec3& p : mesh.positions) box = {glm::min(box.min, stored(p)), glm::max(box.max, stored(p))};
    json attributes = {{"POSITION", 0}};
    json accessors = json::array(
        {{{"bufferView", 0}, {"componentType", TINYGLTF_COMPONENT_TYPE_FLOAT}, {"count", nv}, {"type", "VEC3"},
          {"min", {box.min.x, box.min.y, box.min.z}}, {"max", {box.max.x, box.max.y, box.max.z}}},
         {{"bufferView", 1}, {"componentType", TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT}, {"count", 3 * nt}, {"type", "SCALAR"}}});
    json views = json::array({{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", 12 * nv}, {"target", TINYGLTF_TARGET_ARRAY_BUFFER}},
                              {{"buffer", 0}, {"byteOffset", 12 * nv}, {"byteLength", 12 * nt}, {"target", TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER}}});
    if (scalar) {
        attributes["_SCALAR"] = 2;
        accessors.push_back({{"bufferView", 2}, {"componentType", TINYGLTF_COMPONENT_TYPE_FLOAT}, {"count", nv}, {"type", "SCALAR"}});
        views.push_back({{"buffer", 0}, {"byteOffset", 12 * (nv + nt)}, {"byteLength", 4 * nv}, {"target", TINYGLTF_TARGET_ARRAY_BUFFER}});
    }
    return {{"asset", {{"version", "2.0"}, {"generator", "vfsd"}}},
            {"scene", 0},
            {"scenes", {{{"nodes", {0}}}}},
            {"nodes", {{{"mesh", 0}}}},
            {"meshes", {{{"primitives", {{{"attributes", attributes}, {"indices", 1}, {"mode", kTriangles}}}}}}},
            {"accessors", accessors},
            {"bufferViews", views},
            {"buffers", {{{"byteLength", binary_bytes}}}}};
}

void put_chunk(std::string& out, std::string data, char pad, std::uint32_t type) {
    data.resize((data.size() + 3) / 4 * 4, pad);  // chunks are 4-byte aligned
    put_le(out, static_cast<std::uint32_t>(data.size()));
    put_le(out, type);
    out += data;
}

}  // namespace

std::string write_glb(const TriangleMesh& mesh, const WriteOptions& options) {
    const bool scalar = options.write_scalar && mesh.has_scalar();
    std::string bin;
    for (const Vec3& p : mesh.positions) {
        for (int k = 0; k < 3; ++k) put_le(bin, static_cast<float>(p[k]));
    }
    for (const Triangle& t : mesh.triangles) {
        for (int k = 0; k < 3; ++k) put_le(bin, static_cast<std::uint32_t>(t[k]));
    }
    if (scalar) {
        for (double s : mesh.scalar) put_le(bin, static_cast<float>(s));
    }
    const std::string json = glb_json(mesh, scalar, bin.size()).dump();
    std::string chunks;
    put_chunk(chunks, json, ' ', 0x4E4F534Au);  // "JSON"
    put_chunk(chunks, bin, '\0', 0x004E4942u);  // "BIN"
    std::string out;
    put_le(out, 0x46546C67u);  // "glTF"
    put_le(out, std::uint32_t{2});
    put_le(out, static_cast<std::uint32_t>(12 + chunks.size()));
    return out + chunks;
}

TriangleMesh read_gltf(const std::string& path, const std::string& bytes, bool binary, bool external_files) {
    const tinygltf::Model model = load_model(path, bytes, binary, external_files);
    GltfReader reader{path, model, {}};
    const int scene = model.defaultScene;
    if (scene >= 0 && static_cast<std::size_t>(scene) < model.scenes.size()) {
        add_scene_nodes(reader, model.scenes[scene].nodes);
    } else if (!model.scenes.empty()) {
        for (const tinygltf::Scene& s : model.scenes) add_scene_nodes(reader, s.nodes);
    } else {
        for (std::size_t m = 0; m < model.meshes.size(); ++m) add_mesh(reader, static_cast<int>(m), Mat4(1.0));
    }
    if (!reader.all_have_scalar) reader.mesh.scalar.clear();
    check_mesh(path, reader.mesh);
    return std::move(reader.mesh);
}

}  // namespace vfsd::io
