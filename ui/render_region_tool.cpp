#include "ui/render_region_tool.h"

#include <algorithm>
#include <cmath>

namespace caustica::ui {

RenderRegion region_from_drag(glm::vec2 from, glm::vec2 to, int width, int height) {
    const glm::vec2 low = glm::min(from, to), high = glm::max(from, to);
    if (high.x - low.x < 1.0f || high.y - low.y < 1.0f) return {};
    const RenderRegion touched{static_cast<int>(std::floor(low.x)), static_cast<int>(std::floor(low.y)),
                               static_cast<int>(std::ceil(high.x)), static_cast<int>(std::ceil(high.y))};
    return clamp_region(touched, width, height);
}

std::string region_status(const RenderRegion& region) {
    if (region.empty()) return {};
    return "render region " + std::to_string(region.x0) + "," + std::to_string(region.y0) + " - " +
           std::to_string(region.x1) + "," + std::to_string(region.y1) + " (" + std::to_string(region.width()) +
           " x " + std::to_string(region.height()) + "): passes go there alone, Ctrl+Alt+B clears";
}

}  // namespace caustica::ui
