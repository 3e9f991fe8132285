// The render region as the person draws it on the image (docs/PREVIEW.md, "Render region"):
// Shift+drag, or Ctrl+B and then a drag, gives the rectangle of image pixels every pass then
// goes to. GL-free: the frame (ui/view_app.cpp) feeds it the mouse and draws the outline.
#pragma once

#include "core/render/render_region.h"

#include <glm/glm.hpp>

#include <string>

namespace caustica::ui {

/// The pixels of a width x height image that a box dragged between two image points (in image
/// pixel coordinates, either corner first) touches, clamped to the image. A box thinner than a
/// pixel (a click) is no region.
RenderRegion region_from_drag(glm::vec2 from, glm::vec2 to, int width, int height);

/// The status line's words for a region: "render region 8,12 - 24,28 (16 x 16): passes go there
/// alone, Ctrl+Alt+B clears", or "" for none.
std::string region_status(const RenderRegion& region);

/// A region being drawn: armed by Ctrl+B (the next left drag draws it), or begun by Shift+left press.
struct RegionDrag {
    bool armed = false;    ///< the next left press over the image begins a region (Ctrl+B)
    bool active = false;   ///< a region is being dragged
    glm::vec2 from{0.0f}, to{0.0f};  ///< its corners, in image pixel coordinates

    /// Whether a left press with these modifiers begins a region rather than an orbit.
    bool takes_press(bool shift) const { return armed || shift; }
    /// Begins a region at an image point (disarms Ctrl+B: one drag per press of it).
    void begin(glm::vec2 image_point) {
        active = true;
        armed = false;
        from = to = image_point;
    }
    /// The pixels the region covers so far.
    RenderRegion region(int width, int height) const { return region_from_drag(from, to, width, height); }
};

}  // namespace caustica::ui
