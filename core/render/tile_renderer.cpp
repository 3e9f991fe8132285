#include "core/render/tile_renderer.h"

#include "core/render/random.h"

#include <algorithm>
#include <cmath>
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
            ++counters.samples;
            check_pixel(c, x, y);
            for (int yy = y; yy < y1; ++yy)
                for (int xx = x; xx < x1; ++xx) out.at(xx, yy) = c;
        }
    }
}

void render_first_pass_tile(const TileContext& context, const Tile& tile, Image& out, RayCounters& counters) {
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; x += 8) {
            Ray rays[8];
            int valid[8];
            SurfaceHit hits[8];
            bool found[8];
            for (int i = 0; i < 8; ++i) {
                valid[i] = x + i < tile.x1;
                rays[i] = context.camera->generate(static_cast<float>(x + i) + 0.5f, static_cast<float>(y) + 0.5f);
            }
            context.integrator->scene_intersect8(rays, valid, hits, found);
            float visibility[8][Integrator::packet_lights];
            context.integrator->primary_visibility8(rays, hits, found, visibility, counters);
            for (int i = 0; i < 8 && valid[i]; ++i) {
                // One stream per pixel and pass: the result never depends on which thread runs the tile.
                RandomStream random(context.seed, static_cast<std::uint64_t>(y) * out.width + x + i, 0);
                out.at(x + i, y) = found[i] ? context.integrator->shade_primary_hit(rays[i], hits[i], random, counters, visibility[i])
                                            : context.integrator->background(rays[i].direction);
                if (!found[i]) ++counters.primary;
                ++counters.samples;
                check_pixel(out.at(x + i, y), x + i, y);
            }
        }
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
    const int n = context.aa_grid;
    const float cell = 1.0f / static_cast<float>(n);
    for (int y = tile.y0; y < tile.y1; ++y) {
        for (int x = tile.x0; x < tile.x1; ++x) {
            if (!needs_antialiasing(first_pass, x, y, context.aa_threshold)) continue;
            ++counters.supersampled_pixels;
            if (context.draw_aa) {
                out.at(x, y) = glm::vec3(1.0f, 0.0f, 0.0f);
                continue;
            }
            RandomStream random(context.seed, static_cast<std::uint64_t>(y) * first_pass.width + x, 1);
            glm::vec3 sum(0.0f);
            for (int sy = 0; sy < n; ++sy) {
                for (int sx = 0; sx < n; ++sx) {
                    const float px = static_cast<float>(x) + (static_cast<float>(sx) + random.uniform()) * cell;
                    const float py = static_cast<float>(y) + (static_cast<float>(sy) + random.uniform()) * cell;
                    sum += context.integrator->trace_camera_ray(context.camera->generate(px, py), random, counters);
                    ++counters.samples;
                }
            }
            out.at(x, y) = sum / static_cast<float>(n * n);
            check_pixel(out.at(x, y), x, y);
        }
    }
}

}  // namespace caustica
