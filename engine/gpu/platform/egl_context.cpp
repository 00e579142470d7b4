// Headless GL through EGL with no surface: on a machine with a GPU driver
// (NVIDIA's EGL device platform) or on Mesa (surfaceless platform, llvmpipe
// without X). The passes render into their own framebuffers, so the context needs
// no surface at all (EGL_KHR_surfaceless_context).
//
// The display is the first that initialises of
//   1. EGL_PLATFORM_DEVICE_EXT, device by device (EGL_EXT_device_enumeration),
//   2. EGL_PLATFORM_SURFACELESS_MESA,
//   3. EGL_DEFAULT_DISPLAY.
// VFSD_EGL_PLATFORM=device|surfaceless|default tries only that one, and
// VFSD_EGL_DEVICE=N only device N of the device platform.
//
// Linked against glvnd's libEGL and libOpenGL (never libGL or OSMesa).

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "gpu/context.h"
#include "gpu/gpu_error.h"

namespace vfsd::gpu {
namespace {

constexpr const char* kCpuHint = "; the CPU path (--backend cpu) computes the same deformation";

std::string egl_error_name(EGLint code) {
    switch (code) {
        case EGL_SUCCESS: return "EGL_SUCCESS";
        case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
        case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
        case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
        case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
        case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
        case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
        case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
        case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
        case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
        case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
        case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
        case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
        case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
        case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
        default: {
            char hex[16];
            std::snprintf(hex, sizeof hex, "0x%04X", static_cast<unsigned>(code));
            return hex;
        }
    }
}

std::string last_error() { return egl_error_name(eglGetError()); }

bool has_extension(const char* list, const char* name) {
    if (!list) return false;
    const std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

std::string env(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

// An initialised display, and what was tried on the way (for the error message).
struct Display {
    EGLDisplay handle = EGL_NO_DISPLAY;
    std::string platform;  // "device 0", "surfaceless", "default"
};

bool initialise(EGLDisplay display, const std::string& what, std::vector<std::string>& tried) {
    if (display == EGL_NO_DISPLAY) {
        tried.push_back(what + ": no display (" + last_error() + ")");
        return false;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
        tried.push_back(what + ": eglInitialize failed (" + last_error() + ")");
        return false;
    }
    return true;
}

Display open_display() {
    const std::string only = env("VFSD_EGL_PLATFORM");
    if (!only.empty() && only != "device" && only != "surfaceless" && only != "default")
        throw GpuUnavailable("VFSD_EGL_PLATFORM='" + only + "': expected device, surfaceless or default");
    const auto wanted = [&](const char* name) { return only.empty() || only == name; };

    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);  // null without EGL_EXT_client_extensions
    const auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    const bool platforms = get_platform_display && has_extension(client, "EGL_EXT_platform_base");
    std::vector<std::string> tried;

    if (wanted("device")) {
        const auto query_devices =
            reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        if (!platforms || !query_devices || !has_extension(client, "EGL_EXT_platform_device")) {
            tried.push_back("device platform: not supported by this EGL (EGL_EXT_platform_device)");
        } else {
            EGLint count = 0;
            std::vector<EGLDeviceEXT> devices(16);
            if (!query_devices(static_cast<EGLint>(devices.size()), devices.data(), &count)) {
                tried.push_back("device platform: eglQueryDevicesEXT failed (" + last_error() + ")");
                count = 0;
            } else if (count == 0) {
                tried.push_back("device platform: no EGL device");
            }
            const std::string pick = env("VFSD_EGL_DEVICE");
            bool picked = false;
            for (EGLint i = 0; i < count; ++i) {
                if (!pick.empty() && pick != std::to_string(i)) continue;
                picked = true;
                const std::string what = "device " + std::to_string(i);
                const EGLDisplay display = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
                if (initialise(display, what, tried)) return {display, what};
            }
            if (!pick.empty() && !picked)
                tried.push_back("VFSD_EGL_DEVICE=" + pick + ": there are " + std::to_string(count) + " devices");
        }
    }
    if (wanted("surfaceless")) {
        if (!platforms || !has_extension(client, "EGL_MESA_platform_surfaceless")) {
            tried.push_back("surfaceless platform: not supported by this EGL (EGL_MESA_platform_surfaceless)");
        } else {
            const EGLDisplay display =
                get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
            if (initialise(display, "surfaceless", tried)) return {display, "surfaceless"};
        }
    }
    if (wanted("default")) {
        const EGLDisplay display = eglGetDisplay(EGL_DEFAULT_DISPLAY);
        if (initialise(display, "default display", tried)) return {display, "default"};
    }
    std::string message = "no headless GL context: no EGL display could be initialised";
    for (const std::string& t : tried) message += "; " + t;
    throw GpuUnavailable(message + kCpuHint);
}

class EglContext final : public Context {
public:
    EglContext() {
        const Display display = open_display();
        display_ = display.handle;
        const std::string where = "EGL " + display.platform;
        const char* extensions = eglQueryString(display_, EGL_EXTENSIONS);
        if (!has_extension(extensions, "EGL_KHR_surfaceless_context"))
            throw GpuUnavailable("no headless GL context: " + where + " lacks EGL_KHR_surfaceless_context" + kCpuHint);
        if (!eglBindAPI(EGL_OPENGL_API))
            throw GpuUnavailable("no headless GL context: eglBindAPI(EGL_OPENGL_API) failed on " + where + " (" +
                                 last_error() + ")" + kCpuHint);

        const EGLConfig config = choose_config(extensions, where);
        // GLSL ES 3.00 on desktop GL needs 4.3 (or ARB_ES3_compatibility): ask for
        // 4.5 first, then 4.3, then 3.3, all core.
        std::string failures;
        for (const auto& [major, minor] : {std::pair{4, 5}, std::pair{4, 3}, std::pair{3, 3}}) {
            const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, major, EGL_CONTEXT_MINOR_VERSION, minor,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
            context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, attribs);
            if (context_ != EGL_NO_CONTEXT) break;
            failures += (failures.empty() ? "" : ", ") + std::to_string(major) + "." + std::to_string(minor) +
                        " core: " + last_error();
        }
        if (context_ == EGL_NO_CONTEXT)
            throw GpuUnavailable("no headless GL context: eglCreateContext failed on " + where + " (" + failures +
                                 ")" + kCpuHint);
        make_current();
    }
    ~EglContext() override {
        // The display is left initialised: EGL displays are per process, and
        // eglTerminate would also end any other context on it.
        if (eglGetCurrentContext() == context_)
            eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
    }
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    void make_current() override {
        if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
            throw GpuUnavailable("no headless GL context: eglMakeCurrent without a surface failed (" + last_error() +
                                 ")" + kCpuHint);
    }
    std::string kind() const override { return "egl"; }

private:
    // No config at all where EGL allows it (EGL_KHR_no_config_context); else any
    // config that renders desktop GL, pbuffer or not.
    EGLConfig choose_config(const char* extensions, const std::string& where) const {
        if (has_extension(extensions, "EGL_KHR_no_config_context")) return EGL_NO_CONFIG_KHR;
        const EGLint with_pbuffer[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                       EGL_NONE};
        const EGLint any_surface[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_DONT_CARE,
                                      EGL_NONE};
        for (const EGLint* attribs : {with_pbuffer, any_surface}) {
            EGLConfig config = nullptr;
            EGLint count = 0;
            if (eglChooseConfig(display_, attribs, &config, 1, &count) && count > 0) return config;
        }
        throw GpuUnavailable("no headless GL context: " + where + " has no config for desktop OpenGL (" +
                             last_error() + ")" + kCpuHint);
    }

    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<Context> create_headless_context() { return std::make_unique<EglContext>(); }

}  // namespace vfsd::gpu
