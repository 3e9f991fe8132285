// When and where the hover readout (the pixel inspector beside the cursor, docs/INSPECTION.md)
// shows, GL-free: only once the mouse rests on the image (no drag, no orbit, still for a moment),
// so that it never covers the view being moved to, and in a box that keeps clear of the cursor and
// inside the image area.
#pragma once

#include <glm/glm.hpp>

namespace caustica::ui {

/// Seconds the mouse and the camera must stay still before the readout shows.
inline constexpr double readout_rest_seconds = 0.35;
/// Window pixels between the cursor and the nearest corner of the readout box.
inline constexpr float readout_cursor_gap = 24.0f;
/// Window pixels kept between the box and the image area's edges.
inline constexpr float readout_margin = 4.0f;

/// Follows the mouse and the camera frame by frame and says when the readout may show.
class HoverRest {
public:
    /// One frame at `now` seconds: `active` when the mouse moved, a button is held or the camera
    /// changed in this frame.
    void update(double now, bool active) {
        if (active || !seen_) last_activity_ = now;
        seen_ = true;
    }
    /// Whether everything has been still for readout_rest_seconds at `now`.
    bool resting(double now) const { return seen_ && now - last_activity_ >= readout_rest_seconds - 1e-9; }

private:
    double last_activity_ = 0.0;
    bool seen_ = false;
};

/// The top-left corner of a readout box of `box` pixels for the cursor at `cursor`, in an image
/// area of `area` pixels from the window's top-left: below and right of the cursor by
/// readout_cursor_gap, flipped to the other side where it would leave the area, then kept inside
/// it (a box larger than the area starts at its top-left margin).
glm::vec2 readout_position(glm::vec2 cursor, glm::vec2 box, glm::vec2 area);

}  // namespace caustica::ui
