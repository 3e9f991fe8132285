// The per-tile work of the two image passes: first samples (packets of primary rays) and
// adaptive anti-aliasing of pixels that differ from their neighbours.
#pragma once

#include "core/scene/camera.h"
#include "core/render/image.h"
#include "core/integrators/integrator.h"
#include "core/render/render_region.h"

#include <atomic>
#include <cstdint>
#include <vector>

namespace caustica {

/// A rectangle of pixels [x0, x1) x [y0, y1).
struct Tile {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// Splits an image into tiles of `size` pixels, row by row.
std::vector<Tile> make_tiles(int width, int height, int size);

/// The part of `tile` a pass renders: all of it without a region, else its overlap with the
/// region (empty, x1 <= x0 or y1 <= y0, when the tile keeps its pixels).
inline Tile region_part(const Tile& tile, const RenderRegion& region) {
    if (region.empty()) return tile;
    return {std::max(tile.x0, region.x0), std::max(tile.y0, region.y0), std::min(tile.x1, region.x1),
            std::min(tile.y1, region.y1)};
}

/// Whether a tile (or a part of one) has no pixels.
inline bool tile_empty(const Tile& tile) { return tile.x1 <= tile.x0 || tile.y1 <= tile.y0; }

/// One image of --layers: an integrator that keeps one layer (ShadingSetup::layer) and the image
/// its samples fill, sampled exactly as the image is (the same rays and random streams; the
/// anti-aliasing pass refines the pixels the image's own samples chose).
struct LayerTarget {
    const Integrator* integrator = nullptr;
    Image* image = nullptr;
};

/// Inputs shared by every tile of one render.
struct TileContext {
    const Integrator* integrator = nullptr;
    const Camera* camera = nullptr;
    std::uint64_t seed = 0;
    int aa_grid = 3;
    float aa_threshold = 0.5f;
    bool draw_aa = false;
    /// corner_grid sampling: per pixel, whether its four corner samples differ by more than the
    /// threshold (written by the first pass, read by the anti-aliasing pass; width x height).
    std::vector<std::uint8_t>* refine = nullptr;
    /// The render's cancel flag (null: none). Once it is set a tile stops after the packet (or
    /// sample) being traced and writes nothing of it: what was traced then is not the scene's.
    /// The tile is left incomplete, never to be shown (docs/RELIABILITY.md, "Bounded time").
    const std::atomic<bool>* cancel = nullptr;
    /// --layers: the images the first and anti-aliasing passes also fill (null or empty: none).
    /// Their rays are not counted in the statistics.
    const std::vector<LayerTarget>* layers = nullptr;
};

/// Whether the image needs the anti-aliasing pass after the first one.
bool has_antialiasing_pass(const TileContext& context);

/// One sample per `block` x `block` square (at its centre), filling the whole square: a fast preview.
void render_coarse_tile(const TileContext& context, const Tile& tile, int block, Image& out, RayCounters& counters);

/// The first samples of each pixel, 8 pixels per packet: one through the pixel centre
/// (adaptive_neighbours), or the classic anti-aliasing's grid or its four corners (corner_grid).
void render_first_pass_tile(const TileContext& context, const Tile& tile, Image& out, RayCounters& counters);

/// adaptive_neighbours: whether pixel (x, y) differs from a neighbour by more than the threshold
/// (sum of |RGB| differences of the clamped colours).
bool needs_antialiasing(const Image& first_pass, int x, int y, float threshold);

/// The classic anti-aliasing's difference of the four corner samples of a pixel: the sum over the 6
/// pairs of the squared RGB differences (unclamped).
float corner_difference(const glm::vec3 corners[4]);

/// Replaces pixels that need it by the mean of all N x N samples (jittered for
/// adaptive_neighbours, the regular grid for corner_grid); --draw-aa paints them red.
void render_antialiasing_tile(const TileContext& context, const Tile& tile, const Image& first_pass, Image& out,
                              RayCounters& counters);

}  // namespace caustica
