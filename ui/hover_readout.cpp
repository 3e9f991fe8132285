#include "ui/hover_readout.h"

#include <algorithm>

namespace caustica::ui {
namespace {

/// One axis: after the cursor, else before it, else wherever it fits best.
float place_on_axis(float cursor, float box, float area) {
    const float after = cursor + readout_cursor_gap, before = cursor - readout_cursor_gap - box;
    float at = after + box + readout_margin <= area ? after : before >= readout_margin ? before : after;
    at = std::min(at, area - readout_margin - box);
    return std::max(at, readout_margin);
}

}  // namespace

glm::vec2 readout_position(glm::vec2 cursor, glm::vec2 box, glm::vec2 area) {
    return {place_on_axis(cursor.x, box.x, area.x), place_on_axis(cursor.y, box.y, area.y)};
}

}  // namespace caustica::ui
