// EGL headless context: device platform on NVIDIA, Mesa surfaceless otherwise.
#include "harness/headless_context.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include "fx/error.hpp"

#ifndef EGL_NO_CONFIG_KHR
#define EGL_NO_CONFIG_KHR ((EGLConfig)0)
#endif
#ifndef EGL_DRM_RENDER_NODE_FILE_EXT
#define EGL_DRM_RENDER_NODE_FILE_EXT 0x3377
#endif

namespace cellfx::fx {
namespace {

const char* egl_error_name(EGLint code) {
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
    default: return "unknown EGL error";
    }
}

// "eglInitialize failed: EGL_NOT_INITIALIZED (0x3001)"
[[noreturn]] void throw_egl(const std::string& what) {
    EGLint code = eglGetError();
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%04X", static_cast<unsigned>(code));
    throw Error("headless GL context: " + what + " failed: " + egl_error_name(code) + " (" + hex + ")");
}

// Exact token match in a space-separated extension list (no prefix false positives).
bool has_token(const char* list, const char* token) {
    if (list == nullptr)
        return false;
    const std::size_t n = std::strlen(token);
    for (const char* p = list; (p = std::strstr(p, token)) != nullptr; p += n) {
        const bool starts = p == list || p[-1] == ' ';
        const bool ends = p[n] == ' ' || p[n] == '\0';
        if (starts && ends)
            return true;
    }
    return false;
}

const char* client_extensions() {
    // Null (with EGL_BAD_DISPLAY) on EGL 1.4 without EGL_EXT_client_extensions.
    const char* ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (ext == nullptr)
        eglGetError();
    return ext;
}

// eglTerminate affects every context on a display, and displays are per-platform singletons,
// so terminate only when the last HeadlessContext on a display goes.
std::mutex g_display_mutex;
std::map<EGLDisplay, int> g_display_refs;

void acquire_display(EGLDisplay display) {
    std::lock_guard<std::mutex> lock(g_display_mutex);
    ++g_display_refs[display];
}
void release_display(EGLDisplay display) {
    std::lock_guard<std::mutex> lock(g_display_mutex);
    auto it = g_display_refs.find(display);
    if (it != g_display_refs.end() && --it->second == 0) {
        g_display_refs.erase(it);
        eglTerminate(display);
    }
}

struct DeviceChoice {
    EGLDeviceEXT device = EGL_NO_DEVICE_EXT;
    std::string name;
    bool nvidia = false;
};

// The first hardware EGL device (NVIDIA preferred); device == EGL_NO_DEVICE_EXT if none.
DeviceChoice find_hardware_device() {
    DeviceChoice choice;
    const char* client = client_extensions();
    if (!has_token(client, "EGL_EXT_platform_device") ||
        !(has_token(client, "EGL_EXT_device_enumeration") || has_token(client, "EGL_EXT_device_base")))
        return choice;
    EGLint count = 0;
    if (!eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) {
        eglGetError();
        return choice;
    }
    std::vector<EGLDeviceEXT> devices(static_cast<std::size_t>(count));
    if (!eglQueryDevicesEXT(count, devices.data(), &count)) {
        eglGetError();
        return choice;
    }
    for (EGLint i = 0; i < count; ++i) {
        const char* ext = eglQueryDeviceStringEXT(devices[i], EGL_EXTENSIONS);
        if (ext == nullptr || has_token(ext, "EGL_MESA_device_software"))
            continue; // llvmpipe/softpipe: surfaceless gives the same without the device detour
        const bool nvidia = has_token(ext, "EGL_NV_device_cuda");
        if (choice.device != EGL_NO_DEVICE_EXT && (choice.nvidia || !nvidia))
            continue;
        choice.device = devices[i];
        choice.nvidia = nvidia;
        choice.name.clear();
        const char* file = nullptr;
        if (has_token(ext, "EGL_EXT_device_drm_render_node"))
            file = eglQueryDeviceStringEXT(devices[i], EGL_DRM_RENDER_NODE_FILE_EXT);
        if (file == nullptr && has_token(ext, "EGL_EXT_device_drm"))
            file = eglQueryDeviceStringEXT(devices[i], EGL_DRM_DEVICE_FILE_EXT);
        choice.name = file ? file : ("EGL device " + std::to_string(i));
    }
    return choice;
}

bool nvidia_driver_present(const DeviceChoice& device) {
    std::error_code ignored;
    return device.device != EGL_NO_DEVICE_EXT &&
           (device.nvidia || std::filesystem::exists("/proc/driver/nvidia/version", ignored));
}

EglPlatform platform_from_environment() {
    const char* env = std::getenv("CELLFX_EGL_PLATFORM");
    if (env == nullptr || *env == '\0')
        return EglPlatform::Auto;
    if (std::strcmp(env, "device") == 0)
        return EglPlatform::Device;
    if (std::strcmp(env, "surfaceless") == 0)
        return EglPlatform::Surfaceless;
    throw Error(std::string("CELLFX_EGL_PLATFORM=") + env + ": expected \"device\" or \"surfaceless\"");
}

} // namespace

const char* egl_platform_name(EglPlatform platform) {
    switch (platform) {
    case EglPlatform::Auto: return "auto";
    case EglPlatform::Device: return "device";
    case EglPlatform::Surfaceless: return "surfaceless";
    }
    return "?";
}

struct HeadlessContext::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    EglPlatform platform = EglPlatform::Auto;
    std::string device, vendor, renderer, version;

    Impl() = default;
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;
    ~Impl() {
        if (context != EGL_NO_CONTEXT) {
            if (eglGetCurrentContext() == context)
                eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(display, context);
        }
        if (display != EGL_NO_DISPLAY)
            release_display(display);
    }

    // Initialises `display_` (which `platform` produced) and creates + makes current a 4.5 core
    // context on it. On failure throws; the destructor cleans up what was made.
    void create_on(EGLDisplay new_display, const HeadlessContextOptions& options) {
        EGLint major = 0, minor = 0;
        if (!eglInitialize(new_display, &major, &minor))
            throw_egl(std::string("eglInitialize (") + egl_platform_name(platform) + " platform)");
        display = new_display;
        acquire_display(display);

        const char* ext = eglQueryString(display, EGL_EXTENSIONS);
        const bool egl15 = major > 1 || (major == 1 && minor >= 5);
        if (!egl15 && !has_token(ext, "EGL_KHR_create_context"))
            throw Error("headless GL context: EGL " + std::to_string(major) + "." + std::to_string(minor) +
                        " without EGL_KHR_create_context cannot ask for OpenGL 4.5 core");
        if (!has_token(ext, "EGL_KHR_surfaceless_context"))
            throw Error("headless GL context: the EGL display lacks EGL_KHR_surfaceless_context "
                        "(needed to render with no surface)");
        if (!eglBindAPI(EGL_OPENGL_API))
            throw_egl("eglBindAPI(EGL_OPENGL_API)");

        EGLConfig config = EGL_NO_CONFIG_KHR;
        if (!has_token(ext, "EGL_KHR_no_config_context") && !has_token(ext, "EGL_MESA_configless_context")) {
            const EGLint config_attribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
                                             EGL_NONE};
            EGLint count = 0;
            if (!eglChooseConfig(display, config_attribs, &config, 1, &count))
                throw_egl("eglChooseConfig");
            if (count == 0)
                throw Error("headless GL context: eglChooseConfig found no config that renders OpenGL");
        }

        std::vector<EGLint> attribs = {EGL_CONTEXT_MAJOR_VERSION_KHR, 4, EGL_CONTEXT_MINOR_VERSION_KHR, 5,
                                       EGL_CONTEXT_OPENGL_PROFILE_MASK_KHR,
                                       EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT_KHR};
        if (options.debug_context)
            attribs.insert(attribs.end(), {EGL_CONTEXT_FLAGS_KHR, EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR});
        attribs.push_back(EGL_NONE);
        context = eglCreateContext(display, config, EGL_NO_CONTEXT, attribs.data());
        if (context == EGL_NO_CONTEXT)
            throw_egl("eglCreateContext (OpenGL 4.5 core)");
        if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
            throw_egl("eglMakeCurrent (no surface)");

        auto gl_string = [](GLenum name) {
            const GLubyte* s = glGetString(name);
            return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
        };
        vendor = gl_string(GL_VENDOR);
        renderer = gl_string(GL_RENDERER);
        version = gl_string(GL_VERSION);
        GLint profile = 0;
        glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
        if (epoxy_gl_version() < 45 || (profile & GL_CONTEXT_CORE_PROFILE_BIT) == 0)
            throw Error("headless GL context: asked for OpenGL 4.5 core, got \"" + version + "\" (" + renderer + ")");
    }

    void create_surfaceless(const HeadlessContextOptions& options) {
        platform = EglPlatform::Surfaceless;
        if (!has_token(client_extensions(), "EGL_MESA_platform_surfaceless"))
            throw Error("headless GL context: EGL has no EGL_MESA_platform_surfaceless (Mesa's surfaceless "
                        "platform); install Mesa's EGL or set CELLFX_EGL_PLATFORM=device");
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (d == EGL_NO_DISPLAY)
            throw_egl("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
        create_on(d, options);
    }

    void create_device(const DeviceChoice& choice, const HeadlessContextOptions& options) {
        platform = EglPlatform::Device;
        if (choice.device == EGL_NO_DEVICE_EXT)
            throw Error("headless GL context: no hardware EGL device (EGL_EXT_platform_device + "
                        "EGL_EXT_device_enumeration, non-software device) was found");
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, choice.device, nullptr);
        if (d == EGL_NO_DISPLAY)
            throw_egl("eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, " + choice.name + ")");
        device = choice.name;
        create_on(d, options);
    }
};

HeadlessContext::HeadlessContext(const HeadlessContextOptions& options) {
    if (!epoxy_has_egl())
        throw Error("headless GL context: libEGL.so.1 could not be loaded (install libegl1 and a GL driver: "
                    "Mesa, or the NVIDIA driver)");
    EglPlatform wanted = options.platform;
    if (wanted == EglPlatform::Auto)
        wanted = platform_from_environment();

    if (wanted == EglPlatform::Surfaceless) {
        impl_ = std::make_unique<Impl>();
        impl_->create_surfaceless(options);
        return;
    }
    const DeviceChoice device = find_hardware_device();
    if (wanted == EglPlatform::Device) {
        impl_ = std::make_unique<Impl>();
        impl_->create_device(device, options);
        return;
    }
    // Auto: the device platform where NVIDIA's driver is, falling back to surfaceless.
    std::string device_failure;
    if (nvidia_driver_present(device)) {
        try {
            impl_ = std::make_unique<Impl>();
            impl_->create_device(device, options);
            return;
        } catch (const Error& e) {
            device_failure = e.what();
            impl_.reset();
        }
    }
    try {
        impl_ = std::make_unique<Impl>();
        impl_->create_surfaceless(options);
    } catch (const Error& e) {
        impl_.reset();
        if (device_failure.empty())
            throw;
        throw Error(device_failure + "; then " + e.what());
    }
}

HeadlessContext::~HeadlessContext() = default;
HeadlessContext::HeadlessContext(HeadlessContext&& other) noexcept = default;
HeadlessContext& HeadlessContext::operator=(HeadlessContext&& other) noexcept = default;

void HeadlessContext::make_current() const {
    if (!impl_)
        throw Error("HeadlessContext::make_current on a moved-from context");
    if (eglGetCurrentContext() == impl_->context)
        return;
    if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context))
        throw_egl("eglMakeCurrent (no surface)");
}

bool HeadlessContext::is_current() const {
    return impl_ && eglGetCurrentContext() == impl_->context;
}

namespace {
const std::string kEmpty;
}

EglPlatform HeadlessContext::platform() const { return impl_ ? impl_->platform : EglPlatform::Auto; }
const std::string& HeadlessContext::device() const { return impl_ ? impl_->device : kEmpty; }
const std::string& HeadlessContext::vendor() const { return impl_ ? impl_->vendor : kEmpty; }
const std::string& HeadlessContext::renderer() const { return impl_ ? impl_->renderer : kEmpty; }
const std::string& HeadlessContext::version() const { return impl_ ? impl_->version : kEmpty; }

std::string HeadlessContext::description() const {
    if (!impl_)
        return "(moved-from headless context)";
    std::string s = impl_->renderer + ", OpenGL " + impl_->version + ", EGL " + egl_platform_name(impl_->platform);
    if (!impl_->device.empty())
        s += " " + impl_->device;
    return s;
}

} // namespace cellfx::fx
