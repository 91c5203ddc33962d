// cellfx ParaView plugin — the depth of what VTK has drawn so far, as the texture cellfx reads
// (fx::CellRenderOptions::scene_depth), so that the volume stops at opaque geometry.
//
// When VTK's draw framebuffer has a single-sample GL_TEXTURE_2D depth attachment that cellfx
// can read as it is (level 0, no compare mode, no mipmaps needed), that texture is used: cellfx
// unbinds it before it draws into the framebuffer. Otherwise (a renderbuffer, a multisampled
// texture, the window's own framebuffer) the viewport's depth is copied with
// glBlitNamedFramebuffer into a texture of the same format, which changes no binding.
//
// Raw GL through libepoxy, kept apart from VTK's headers (which bring their own GL loader).
// Every call needs the GL context that VTK renders with current; release() before it goes.
#pragma once

#include <string>

namespace cellfx_paraview {

class SceneDepth {
public:
    SceneDepth() = default;
    SceneDepth(const SceneDepth&) = delete;
    SceneDepth& operator=(const SceneDepth&) = delete;

    // The depth texture for the viewport (x, y, width, height) of the current draw framebuffer,
    // 0 when that framebuffer has no depth. `how` says which way it was obtained (for logs).
    unsigned int texture_for_current_framebuffer(int x, int y, int width, int height, std::string& how);
    // Deletes the copy's GL objects (the context they were made in must be current).
    void release();
    // Forgets them without a GL call: their context is gone, and they with it.
    void abandon() { texture_ = framebuffer_ = 0, width_ = height_ = format_ = 0; }

private:
    unsigned int texture_ = 0, framebuffer_ = 0;
    int width_ = 0, height_ = 0;
    int format_ = 0;
};

} // namespace cellfx_paraview
