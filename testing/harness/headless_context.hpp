// cellfx — an OpenGL 4.5 core context with no window and no surface (tests, the CLI, batch
// rendering). Games do not need this: cellfx renders into whatever context they have current.
//
// Created through EGL, with libepoxy as the GL loader:
//   - the EGL device platform (EGL_EXT_platform_device) on a hardware device where an NVIDIA
//     driver is present — headless rendering on GPU servers;
//   - otherwise Mesa's surfaceless platform (EGL_MESA_platform_surfaceless), e.g. llvmpipe on
//     machines without a GPU.
// The environment variable CELLFX_EGL_PLATFORM=device|surfaceless forces one when the options
// ask for Auto. No window system (X11, Wayland) is used. Rendering goes into framebuffer
// objects: the context has no default framebuffer.
//
// Ownership: the object owns the EGL context (and one reference to its EGL display, which is
// terminated when the last HeadlessContext on it goes). Move-only. GL objects made while it
// is current must be destroyed before it is.
#pragma once

#include <memory>
#include <string>

namespace cellfx::fx {

enum class EglPlatform {
    Auto,        // CELLFX_EGL_PLATFORM if set, else device with an NVIDIA driver, else surfaceless
    Device,      // EGL_EXT_platform_device, first non-software device
    Surfaceless, // EGL_MESA_platform_surfaceless
};
const char* egl_platform_name(EglPlatform platform); // "auto", "device", "surfaceless"

struct HeadlessContextOptions {
    EglPlatform platform = EglPlatform::Auto;
    bool debug_context = false; // ask for a GL debug context (KHR_debug output)
};

class HeadlessContext {
public:
    // Creates the context and makes it current on the calling thread. Throws fx::Error naming
    // the step that failed (loading libEGL, the platform extension, eglInitialize,
    // eglCreateContext for 4.5 core, ...) and the EGL error code.
    explicit HeadlessContext(const HeadlessContextOptions& options = {});
    ~HeadlessContext();
    HeadlessContext(HeadlessContext&& other) noexcept;
    HeadlessContext& operator=(HeadlessContext&& other) noexcept;
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;

    // Makes this context current on the calling thread (a context is current on at most one
    // thread at a time). Throws fx::Error on failure or on a moved-from object.
    void make_current() const;
    bool is_current() const;

    EglPlatform platform() const;    // the platform actually used (never Auto)
    const std::string& device() const;   // the EGL device used ("/dev/dri/renderD128", ...) or ""
    const std::string& vendor() const;   // GL_VENDOR
    const std::string& renderer() const; // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    const std::string& version() const;  // GL_VERSION, e.g. "4.5 (Core Profile) Mesa 22.3.6"
    std::string description() const;    // one line: renderer, version, platform

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace cellfx::fx
