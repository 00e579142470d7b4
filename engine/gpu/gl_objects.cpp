#include "gpu/gl_objects.h"

#include <algorithm>
#include <atomic>
#include <cstdio>

#include "gpu/gpu_error.h"
#include "gpu/shader_sources.h"

namespace vfsd::gpu {
namespace {

std::atomic<std::uint64_t> g_readbacks{0};

const char* gl_error_name(GLenum e) {
    switch (e) {
        case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
        default: return "unknown GL error";
    }
}

// Compiles one stage from the prelude and the named files; "#line 1 k" makes the
// driver's log say "k:LINE", where k indexes `files`.
GLuint compile_stage(GLenum stage, const std::string& program, const std::vector<std::string>& files) {
    std::string text = shader_prelude();
    for (std::size_t k = 0; k < files.size(); ++k)
        text += "#line 1 " + std::to_string(k + 1) + "\n" + shader_source(files[k]) + "\n";
    const GLuint shader = glCreateShader(stage);
    const char* source = text.c_str();
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok) return shader;
    GLint length = 0;
    glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetShaderInfoLog(shader, length, nullptr, log.data());
    glDeleteShader(shader);
    std::string names;
    for (std::size_t k = 0; k < files.size(); ++k) names += " " + std::to_string(k + 1) + "=" + files[k];
    throw GpuError("shader program '" + program + "': " + (stage == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                   " stage does not compile (sources:" + names + "):\n" + log.c_str());
}

}  // namespace

void check_gl(const char* what) {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR) throw GpuError(std::string(what) + ": " + gl_error_name(e));
}

void check_gl_in_frame([[maybe_unused]] const char* what) {
#ifndef __EMSCRIPTEN__
    check_gl(what);
#endif
}

namespace detail {
void delete_texture(GLuint id) { glDeleteTextures(1, &id); }
void delete_framebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void delete_program(GLuint id) { glDeleteProgram(id); }
void delete_buffer(GLuint id) { glDeleteBuffers(1, &id); }
void delete_vertex_array(GLuint id) { glDeleteVertexArrays(1, &id); }
void delete_renderbuffer(GLuint id) { glDeleteRenderbuffers(1, &id); }
}  // namespace detail

// ---- Texture ----

Texture::Texture(GLenum internal_format, int width, int height) : format_(internal_format), width_(width), height_(height) {
    GLuint id = 0;
    glGenTextures(1, &id);
    name_.reset(id);
    glBindTexture(GL_TEXTURE_2D, id);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexStorage2D(GL_TEXTURE_2D, 1, internal_format, width, height);
    check_gl("creating a texture");
}

void Texture::upload(const float* rgba) {
    glBindTexture(GL_TEXTURE_2D, id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGBA, GL_FLOAT, rgba);
    // The CPU path's positions, every drawn frame; a set-up's upload (the GPU passes)
    // is checked by the set-up's own check_gl in WebGL, as GL errors stay until read.
    check_gl_in_frame("uploading a float texture");
}

void Texture::upload(const std::int32_t* data) {
    glBindTexture(GL_TEXTURE_2D, id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    const GLenum layout = format_ == GL_RGBA32I ? GL_RGBA_INTEGER
                          : format_ == GL_RG32I ? GL_RG_INTEGER
                                                : GL_RED_INTEGER;
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, layout, GL_INT, data);
    check_gl("uploading an integer texture");
}

void Texture::bind(int unit) const {
    glActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(GL_TEXTURE_2D, id());
}

// ---- Framebuffer ----

Framebuffer::Framebuffer(const Texture& colour, bool with_depth) : width_(colour.width()), height_(colour.height()) {
    GLuint id = 0;
    glGenFramebuffers(1, &id);
    name_.reset(id);
    glBindFramebuffer(GL_FRAMEBUFFER, id);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour.id(), 0);
    if (with_depth) {
        GLuint rb = 0;
        glGenRenderbuffers(1, &rb);
        depth_.reset(rb);
        glBindRenderbuffer(GL_RENDERBUFFER, rb);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width_, height_);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb);
    }
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw GpuError("framebuffer incomplete (status 0x" + [&] {
            char hex[16];
            std::snprintf(hex, sizeof hex, "%x", status);
            return std::string(hex);
        }() + ") for a " + std::to_string(width_) + "x" + std::to_string(height_) + " texture");
}

void Framebuffer::bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, name_.id());
    glViewport(0, 0, width_, height_);
}

std::vector<float> Framebuffer::read_rgba32f() const {
    std::vector<float> data(static_cast<std::size_t>(width_) * height_ * 4);
    glBindFramebuffer(GL_FRAMEBUFFER, name_.id());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_FLOAT, data.data());
    check_gl("reading a float texture back");
    ++g_readbacks;
    return data;
}

std::vector<std::uint8_t> Framebuffer::read_rgba8() const {
    std::vector<std::uint8_t> data(static_cast<std::size_t>(width_) * height_ * 4);
    glBindFramebuffer(GL_FRAMEBUFFER, name_.id());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, data.data());
    check_gl("reading an image back");
    ++g_readbacks;
    return data;
}

std::uint64_t readback_count() { return g_readbacks.load(); }

// ---- Program ----

Program::Program(std::string name, const std::vector<std::string>& vertex_files,
                 const std::vector<std::string>& fragment_files)
    : program_name_(std::move(name)) {
    const GLuint vs = compile_stage(GL_VERTEX_SHADER, program_name_, vertex_files);
    GLuint fs = 0;
    try {
        fs = compile_stage(GL_FRAGMENT_SHADER, program_name_, fragment_files);
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    const GLuint id = glCreateProgram();
    name_.reset(id);
    glAttachShader(id, vs);
    glAttachShader(id, fs);
    glLinkProgram(id);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = GL_FALSE;
    glGetProgramiv(id, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetProgramiv(id, GL_INFO_LOG_LENGTH, &length);
        std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
        glGetProgramInfoLog(id, length, nullptr, log.data());
        throw GpuError("shader program '" + program_name_ + "' does not link:\n" + log.c_str());
    }
}

void Program::use() const { glUseProgram(name_.id()); }
GLint Program::location(const char* uniform) const {
    const auto [it, added] = locations_.try_emplace(uniform, -1);
    if (added) it->second = glGetUniformLocation(name_.id(), uniform);
    return it->second;
}
void Program::set(const char* uniform, int value) const { glUniform1i(location(uniform), value); }
void Program::set(const char* uniform, int x, int y) const { glUniform2i(location(uniform), x, y); }
void Program::set(const char* uniform, float value) const { glUniform1f(location(uniform), value); }
void Program::set(const char* uniform, float x, float y, float z) const { glUniform3f(location(uniform), x, y, z); }
void Program::set(const char* uniform, float x, float y, float z, float w) const {
    glUniform4f(location(uniform), x, y, z, w);
}
void Program::set_mat4(const char* uniform, const float* m) const { glUniformMatrix4fv(location(uniform), 1, GL_FALSE, m); }

// ---- Buffer, VertexArray ----

Buffer::Buffer(GLenum target, const void* data, std::size_t bytes) {
    GLuint id = 0;
    glGenBuffers(1, &id);
    name_.reset(id);
    glBindBuffer(target, id);
    glBufferData(target, static_cast<GLsizeiptr>(bytes), data, GL_STATIC_DRAW);
    check_gl("creating a buffer");
}

void Buffer::update(GLenum target, const void* data, std::size_t bytes) {
    if (id() == 0) {
        GLuint id = 0;
        glGenBuffers(1, &id);
        name_.reset(id);
    }
    glBindBuffer(target, id());
    glBufferData(target, static_cast<GLsizeiptr>(bytes), data, GL_DYNAMIC_DRAW);
    check_gl_in_frame("updating a buffer");
}

VertexArray::VertexArray() {
    GLuint id = 0;
    glGenVertexArrays(1, &id);
    name_.reset(id);
}

void VertexArray::bind() const { glBindVertexArray(name_.id()); }

Fence& Fence::operator=(Fence&& o) noexcept {
    if (this != &o) {
        reset();
        sync_ = std::exchange(o.sync_, nullptr);
    }
    return *this;
}

Fence Fence::issue() {
    Fence fence;
    fence.sync_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    glFlush();
    return fence;
}

bool Fence::signaled() const {
    if (!sync_) return true;
    GLint status = GL_UNSIGNALED;
    glGetSynciv(sync_, GL_SYNC_STATUS, 1, nullptr, &status);
    return status == GL_SIGNALED;
}

void Fence::reset() {
    if (sync_) glDeleteSync(sync_);
    sync_ = nullptr;
}

}  // namespace vfsd::gpu
