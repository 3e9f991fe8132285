// A render region: the rectangle of pixels the image passes render while every other pixel keeps
// what it holds (docs/PREVIEW.md, "Render region"). The preview sets one to sharpen a caustic in
// seconds; a progressive accumulation keeps its sums everywhere, so a region can change without
// restarting it.
#pragma once

#include <algorithm>

namespace caustica {

/// Pixels [x0, x1) x [y0, y1); an empty rectangle means no region: the whole image.
struct RenderRegion {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;

    /// Whether it is no region (the passes render every pixel).
    bool empty() const { return x1 <= x0 || y1 <= y0; }
    int width() const { return empty() ? 0 : x1 - x0; }
    int height() const { return empty() ? 0 : y1 - y0; }
    /// Whether the passes render pixel (x, y): every pixel without a region.
    bool renders(int x, int y) const { return empty() || (x >= x0 && x < x1 && y >= y0 && y < y1); }
    bool operator==(const RenderRegion&) const = default;
};

/// The part of `region` inside a width x height image. A region wholly outside the image is no
/// region (the whole image), never a render of nothing.
inline RenderRegion clamp_region(const RenderRegion& region, int width, int height) {
    RenderRegion r{std::clamp(region.x0, 0, width), std::clamp(region.y0, 0, height), std::clamp(region.x1, 0, width),
                   std::clamp(region.y1, 0, height)};
    return r.empty() ? RenderRegion{} : r;
}

}  // namespace caustica
