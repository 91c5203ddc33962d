// cellfx ParaView plugin — the scan-line renderer's frame composited over what VTK has drawn:
// its premultiplied colour and alpha 1 − e^(−τ) uploaded as a float texture and drawn with
// "over" (fx::gl::CompositePass::draw_over_framebuffer) into the viewport, which is what the
// GL absorption paths' resolve does, so IceT composites the ranks' images the same way.
//
// Raw GL through libepoxy, kept apart from VTK's headers (which bring their own GL loader).
// Every call needs the GL context that VTK renders with current; release() before it goes.
#pragma once

#include <memory>

#include "fx/image.hpp"

namespace cellfx_paraview {

class ScanlineImage {
public:
    ScanlineImage();
    ~ScanlineImage(); // abandons (no GL call): release() first while the context lives
    ScanlineImage(const ScanlineImage&) = delete;
    ScanlineImage& operator=(const ScanlineImage&) = delete;

    // Draws `image` (width × height of the viewport, bottom row first) over the current draw
    // framebuffer at (x, y); restores the viewport and every other GL state it changes.
    void draw_over(const cellfx::fx::Image& image, int x, int y);
    // Deletes the GL objects (the context they were made in must be current).
    void release();
    // Forgets them without a GL call: their context is gone, and they with it.
    void abandon();

private:
    struct Gl;
    std::unique_ptr<Gl> gl_;
};

} // namespace cellfx_paraview
