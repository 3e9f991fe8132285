#include "core/render/tile_renderer.h"

#include "core/render/random.h"
#include "core/util/cancel_flag.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

namespace caustica {
namespace {

/// Debug builds check every pixel: a NaN or infinity is a bug to find, not a value to clamp.
inline void check_pixel([[maybe_unused]] const glm::vec3& c, [[maybe_unused]] int x, [[maybe_unused]] int y) {
#ifndef NDEBUG
    if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)))
        throw std::logic_error("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is not finite: (" +
                               std::to_string(c.x) + ", " + std::to_string(c.y) + ", " + std::to_string(c.z) + ")");
#endif
}

}  // namespace

std::vector<Tile> make_tiles(int width, int height, int size) {
    std::vector<Tile> tiles;
    for (int y = 0; y < height; y += size)
        for (int x = 0; x < width; x += size) tiles.push_back({x, y, std::min(x + size, width), std::min(y + size, height)});
    return tiles;
}

void render_coarse_tile(const TileContext& context, const Tile& tile, int block, Image& out, RayCounters& counters) {
    for (int y = tile.y0; y < tile.y1; y += block) {
        for (int x = tile.x0; x < tile.x1; x += block) {
            const int x1 = std::min(x + block, tile.x1), y1 = std::min(y + block, tile.y1);
            RandomStream random(context.seed, static_cast<std::uint64_t>(y) * out.width + x, 2);
            const glm::vec3 c = context.integrator->trace_camera_ray(
                context.camera->generate(0.5f * static_cast<float>(x + x1), 0.5f * static_cast<float>(y + y1)), random,
                counters);
            if (is_cancelled(context.cancel)) return;
            ++counters.samples;
            check_pixel(c, x, y);
            for (int yy = y; yy < y1; ++yy)
                for (int xx = x; xx < x1; ++xx) out.at(xx, yy) = c;
        }
    }
}

bool has_antialiasing_pass(const TileContext& context) {
    if (context.integrator->pixel_sampling() == PixelSampling::corner_grid) return context.aa_grid > 2;
    return context.aa_grid > 1;
}

float corner_difference(const glm::vec3 corners[4]) {
    float delta = 0.0f;
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) {
            const glm::vec3 d = corners[i] - corners[j];
            delta += glm::dot(d, d);
        }
    return delta;
}

namespace {

/// Traces, for up to 8 pixels of a row, one sample each at the offset (ox, oy) inside the pixel.
void trace_row8(const TileContext& context, const Integrator& integrator, int x, int x_end, int y, float ox, float oy,
                int pass, int width, glm::vec3* out, RayCounters& counters) {
    Ray rays[8];
    int valid[8];
    RandomStream streams[8] = {{0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}, {0, 0}};
    for (int i = 0; i < 8; ++i) {
        valid[i] = x + i < x_end;
        rays[i] = context.camera->generate(static_cast<float>(x + i) + ox, static_cast<float>(y) + oy);
        // One stream per pixel and pass: the result never depends on which thread runs the tile.
        streams[i] = RandomStream(context.seed, static_cast<std::uint64_t>(y) * width + x + i, pass);
    }
    integrator.trace_camera_rays8(rays, valid, streams, out, counters);
    for (int i = 0; i < 8; ++i) counters.samples += valid[i] ? 1 : 0;
}

/// The first samples of up to 8 pixels of a row through `integrator` into `out`; with
/// `record_refine`, the classic anti-aliasing's choice of the pixels to refine. False when cancelled.
bool first_samples8(const TileContext& context, const Integrator& integrator, int x, int x_end, int y, Image& out,
                    bool record_refine, RayCounters& counters) {
    const int count = std::min(8, x_end - x);
    if (integrator.pixel_sampling() != PixelSampling::corner_grid) {
        glm::vec3 c[8];
        trace_row8(context, integrator, x, x_end, y, 0.5f, 0.5f, 0, out.width, c, counters);
        if (is_cancelled(context.cancel)) return false;
        for (int i = 0; i < count; ++i) {
            out.at(x + i, y) = c[i];
            check_pixel(c[i], x + i, y);
        }
        return true;
    }
    // Classic anti-aliasing: the whole regular grid when g <= 2, else its four corner samples.
    const int g = std::max(context.aa_grid, 1);
    const float cell = 1.0f / static_cast<float>(g);
    glm::vec3 sum[8] = {};
    glm::vec3 corner[8][4];
    int k = 0;
    for (int sy = 0; sy < g; ++sy) {
        for (int sx = 0; sx < g; ++sx) {
            const bool is_corner = (sx == 0 || sx == g - 1) && (sy == 0 || sy == g - 1);
            if (g > 2 && !is_corner) continue;
            glm::vec3 c[8];
            trace_row8(context, integrator, x, x_end, y, (static_cast<float>(sx) + 0.5f) * cell,
                       (static_cast<float>(sy) + 0.5f) * cell, 0, out.width, c, counters);
            if (is_cancelled(context.cancel)) return false;
            for (int i = 0; i < count; ++i) {
                sum[i] += c[i];
                if (k < 4) corner[i][k] = c[i];
            }
            ++k;
        }
    }
    for (int i = 0; i < count; ++i) {
        out.at(x + i, y) = sum[i] / static_cast<float>(k);
        check_pixel(out.at(x + i, y), x + i, y);
        if (record_refine && g > 2 && context.refine)
            (*context.refine)[static_cast<std::size_t>(y) * out.width + x + i] =
                corner_difference(corner[i]) > context.aa_threshold;
    }
    return true;
}

/// The anti-aliased value of pixel (x, y) through `integrator`, whose first pass gave `first`;
/// nullopt when cancelled.
std::optional<glm::vec3> antialiased_pixel(const TileContext& context, const Integrator& integrator, int x, int y,
                                           int width, const glm::vec3& first, RayCounters& counters) {
    const bool corners = integrator.pixel_sampling() == PixelSampling::corner_grid;
    const int n = context.aa_grid;
    const float cell = 1.0f / static_cast<float>(n);
    RandomStream random(context.seed, static_cast<std::uint64_t>(y) * width + x, 1);
    // corner_grid: the four corners are in the first pass's mean already.
    glm::vec3 sum = corners ? 4.0f * first : glm::vec3(0.0f);
    for (int sy = 0; sy < n; ++sy) {
        for (int sx = 0; sx < n; ++sx) {
            float ox, oy;
            if (corners) {
                if ((sx == 0 || sx == n - 1) && (sy == 0 || sy == n - 1)) continue;
                ox = (static_cast<float>(sx) + 0.5f) * cell;
                oy = (static_cast<float>(sy) + 0.5f) * cell;
            } else {
                ox = (static_cast<float>(sx) + random.uniform()) * cell;
                oy = (static_cast<float>(sy) + random.uniform()) * cell;
            }
            sum += integrator.trace_camera_ray(
                context.camera->generate(static_cast<float>(x) + ox, static_cast<float>(y) + oy), random, counters);
            if (is_cancelled(context.cancel)) return std::nullopt;
            ++counters.samples;
        }
    }
    return sum / static_cast<float>(n * n);
}

}  // namespace

void render_first_pass_tile(const TileContext& context, const Tile& tile, Image& out, RayCounters& counters) {
    RayCounters layer_counters;  // the layers' rays are not the render's
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; x += 8) {
            if (!first_samples8(context, *context.integrator, x, tile.x1, y, out, true, counters)) return;
            if (context.layers)
                for (const LayerTarget& layer : *context.layers)
                    if (!first_samples8(context, *layer.integrator, x, tile.x1, y, *layer.image, false, layer_counters))
                        return;
        }
}

bool needs_antialiasing(const Image& first_pass, int x, int y, float threshold) {
    const glm::vec3 centre = glm::clamp(first_pass.at(x, y), 0.0f, 1.0f);
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            const int nx = x + dx, ny = y + dy;
            if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= first_pass.width || ny >= first_pass.height) continue;
            const glm::vec3 d = glm::abs(glm::clamp(first_pass.at(nx, ny), 0.0f, 1.0f) - centre);
            if (d.x + d.y + d.z > threshold) return true;
        }
    }
    return false;
}

void render_antialiasing_tile(const TileContext& context, const Tile& tile, const Image& first_pass, Image& out,
                              RayCounters& counters) {
    const bool corners = context.integrator->pixel_sampling() == PixelSampling::corner_grid;
    RayCounters layer_counters;  // the layers' rays are not the render's
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) {
            const bool refine = corners ? context.refine && (*context.refine)[static_cast<std::size_t>(y) * first_pass.width + x]
                                        : needs_antialiasing(first_pass, x, y, context.aa_threshold);
            if (!refine) continue;
            ++counters.supersampled_pixels;
            if (context.draw_aa) {
                out.at(x, y) = glm::vec3(1.0f, 0.0f, 0.0f);
                continue;
            }
            const std::optional<glm::vec3> value =
                antialiased_pixel(context, *context.integrator, x, y, first_pass.width, first_pass.at(x, y), counters);
            if (!value) return;
            out.at(x, y) = *value;
            check_pixel(out.at(x, y), x, y);
            if (!context.layers) continue;
            // A layer pixel holds its first pass until here: the only value of it this reads.
            for (const LayerTarget& layer : *context.layers) {
                Image& image = *layer.image;
                const std::optional<glm::vec3> v =
                    antialiased_pixel(context, *layer.integrator, x, y, first_pass.width, image.at(x, y), layer_counters);
                if (!v) return;
                image.at(x, y) = *v;
            }
        }
    }
}

}  // namespace caustica
