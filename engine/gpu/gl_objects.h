#pragma once
// Small RAII owners of GL objects: each is move-only and deletes its object when
// it goes out of scope. They need a current context for their whole life.

#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "gpu/gl.h"

namespace vfsd::gpu {

// Throws GpuError naming `what` and the GL error code if glGetError reports one.
void check_gl(const char* what);
// The same for the calls of a drawn frame, natively (the desktop, the tests). In
// WebGL glGetError is a synchronous round trip that waits for the GPU process to
// finish what the frame drew (SwiftShader: 60-110 ms for the armadillo), so the
// page does not ask every frame; set-up and read-backs keep check_gl.
void check_gl_in_frame(const char* what);

// Owns one GL name and the function that deletes it.
template <void (*Delete)(GLuint)>
class GlName {
public:
    GlName() = default;
    explicit GlName(GLuint id) : id_(id) {}
    GlName(GlName&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
    GlName& operator=(GlName&& o) noexcept {
        if (this != &o) reset(std::exchange(o.id_, 0));
        return *this;
    }
    GlName(const GlName&) = delete;
    GlName& operator=(const GlName&) = delete;
    ~GlName() { reset(0); }
    GLuint id() const { return id_; }
    void reset(GLuint id) {
        if (id_) Delete(id_);
        id_ = id;
    }

private:
    GLuint id_ = 0;
};

namespace detail {
void delete_texture(GLuint id);
void delete_framebuffer(GLuint id);
void delete_program(GLuint id);
void delete_buffer(GLuint id);
void delete_vertex_array(GLuint id);
void delete_renderbuffer(GLuint id);
}  // namespace detail

// A 2D texture of `width` x `height` texels with nearest filtering, for texelFetch.
// Formats used: GL_RGBA32F (float data), GL_RG32I / GL_R32I (integer data), GL_RGBA8.
class Texture {
public:
    Texture() = default;
    Texture(GLenum internal_format, int width, int height);
    // Uploads a full image of 4 (RGBA32F, RGBA32I), 2 (RG32I) or 1 (R32I) components per texel.
    void upload(const float* rgba);
    void upload(const std::int32_t* data);
    GLuint id() const { return name_.id(); }
    int width() const { return width_; }
    int height() const { return height_; }
    GLenum format() const { return format_; }
    void bind(int unit) const;

private:
    GlName<detail::delete_texture> name_;
    GLenum format_ = 0;
    int width_ = 0, height_ = 0;
};

// A framebuffer rendering into one colour texture (and optionally a depth buffer).
class Framebuffer {
public:
    Framebuffer() = default;
    // Attaches `colour`; throws GpuError when the framebuffer is incomplete (e.g.
    // float render targets are not supported).
    explicit Framebuffer(const Texture& colour, bool with_depth = false);
    void bind() const;
    // Reads the whole RGBA32F colour texture back (counted, see readback_count()).
    std::vector<float> read_rgba32f() const;
    // Reads the whole RGBA8 colour texture back, bottom row first (counted).
    std::vector<std::uint8_t> read_rgba8() const;
    int width() const { return width_; }
    int height() const { return height_; }

private:
    GlName<detail::delete_framebuffer> name_;
    GlName<detail::delete_renderbuffer> depth_;
    int width_ = 0, height_ = 0;
};

// Every read-back from GPU memory goes through Framebuffer::read_*; this counts
// them over the process, so a test can assert that integration reads nothing back.
std::uint64_t readback_count();

// A linked vertex + fragment program. Each stage is a list of named source files
// (see shader_sources.h) concatenated after the version line and the precision
// prelude; compile and link errors throw GpuError with the program's name, the
// file names and the driver's info log.
class Program {
public:
    Program() = default;
    Program(std::string name, const std::vector<std::string>& vertex_files,
            const std::vector<std::string>& fragment_files);
    void use() const;
    GLuint id() const { return name_.id(); }
    const std::string& name() const { return program_name_; }
    // Uniform setters for the program in use (unknown names are ignored, as GL does).
    void set(const char* uniform, int value) const;
    void set(const char* uniform, int x, int y) const;
    void set(const char* uniform, float value) const;
    void set(const char* uniform, float x, float y, float z) const;
    void set(const char* uniform, float x, float y, float z, float w) const;
    void set_mat4(const char* uniform, const float* column_major) const;

private:
    GLint location(const char* uniform) const;
    GlName<detail::delete_program> name_;
    std::string program_name_;
    // Uniform locations by name, looked up once: a step sets about 60 (three
    // Motion structs with the gauge's coefficients), each a driver call otherwise.
    mutable std::unordered_map<std::string, GLint> locations_;
};

// A buffer object (vertex or index data).
class Buffer {
public:
    Buffer() = default;
    Buffer(GLenum target, const void* data, std::size_t bytes);
    // New contents, in the same buffer (a drawn frame's: checked by check_gl_in_frame).
    void update(GLenum target, const void* data, std::size_t bytes);
    GLuint id() const { return name_.id(); }

private:
    GlName<detail::delete_buffer> name_;
};

// A fence after the commands issued so far: signaled() tells whether the GPU has
// executed them, without waiting (a read-back waits; in WebGL the page's main
// thread would wait for the GPU process, SwiftShader's passes included).
class Fence {
public:
    Fence() = default;
    Fence(Fence&& o) noexcept : sync_(std::exchange(o.sync_, nullptr)) {}
    Fence& operator=(Fence&& o) noexcept;
    Fence(const Fence&) = delete;
    Fence& operator=(const Fence&) = delete;
    ~Fence() { reset(); }
    // Inserts the fence and flushes, so that the GPU starts on what came before it.
    static Fence issue();
    bool signaled() const;
    void reset();

private:
    GLsync sync_ = nullptr;
};

// A vertex array object; the fullscreen passes draw with an empty one.
class VertexArray {
public:
    VertexArray();
    void bind() const;

private:
    GlName<detail::delete_vertex_array> name_;
};

}  // namespace vfsd::gpu
