// RenderSession with other ranks (docs/SCALING.md): each preparing step ends at a checkpoint
// where every rank says how it went, and the classic tile passes are handed out by rank 0 in
// batches, their pixels (and anti-aliasing flags) sent back as bytes.
#include "core/render/render_session.h"

#include "core/render/session_passes.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <exception>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>

namespace caustica {

void RenderSession::run_distributed(tbb::task_arena& arena, int threads) {
    // Each step runs locally, then every rank says how it went: a failure on any rank stops them
    // all at the same point. (A ClusterError was agreed on by every rank already: passed on.)
    auto step = [&](auto&& body) {
        std::exception_ptr error;
        try {
            body();
        } catch (const ClusterError&) {
            throw;
        } catch (const InputError& e) {
            error = std::make_exception_ptr(job_.located_option_error(e));
        } catch (const std::bad_alloc&) {  // said as one process says it (app/render_plan.cpp)
            error = std::make_exception_ptr(
                InputError(job_.where, "gr.render: not enough memory to render " + std::to_string(job_.width) + " x " +
                                           std::to_string(job_.height) +
                                           " pixels on this machine; lower the resolution or the photon count"));
        } catch (...) {
            error = std::current_exception();
        }
        cluster_->checkpoint(error, &cancel_requested_);
    };
    step([&] { prepare_checked_scene(); });
    step([&] { prepare_caustics(); });
    {
        std::lock_guard lock(mutex_);
        progress_.prepared = true;
    }
    step([&] { render_passes(arena, threads); });
}

// A tile's result: its pixels, row by row, then (classic) its pixels' corner_grid refine flags.
Cluster::Bytes RenderSession::tile_bytes(int first, int last, const std::vector<LayerTarget>* layers) const {
    Cluster::Bytes bytes;
    for (int i = first; i < last; ++i) {
        const Tile& t = tiles_[static_cast<std::size_t>(i)];
        const std::size_t width = static_cast<std::size_t>(t.x1 - t.x0);
        for (int y = t.y0; y < t.y1; ++y) {
            const auto* row = reinterpret_cast<const std::uint8_t*>(&image_.at(t.x0, y));
            bytes.insert(bytes.end(), row, row + sizeof(glm::vec3) * width);
            const std::uint8_t* flags = refine_.data() + static_cast<std::size_t>(y) * image_.width + t.x0;
            bytes.insert(bytes.end(), flags, flags + width);
            if (layers)
                for (const LayerTarget& layer : *layers) {
                    const auto* layer_row = reinterpret_cast<const std::uint8_t*>(&layer.image->at(t.x0, y));
                    bytes.insert(bytes.end(), layer_row, layer_row + sizeof(glm::vec3) * width);
                }
        }
    }
    return bytes;
}

void RenderSession::put_tile_bytes(int first, int last, const Cluster::Bytes& bytes,
                                   const std::vector<LayerTarget>* layers) {
    const std::size_t layer_count = layers ? layers->size() : 0;
    std::size_t at = 0;
    for (int i = first; i < last; ++i) {
        const std::size_t index = static_cast<std::size_t>(i);
        const Tile& t = tiles_[index];
        const std::size_t width = static_cast<std::size_t>(t.x1 - t.x0), pixel_bytes = sizeof(glm::vec3) * width,
                          row_bytes = (sizeof(glm::vec3) * (1 + layer_count) + 1) * width;
        if (at + row_bytes * static_cast<std::size_t>(t.y1 - t.y0) > bytes.size())
            throw std::runtime_error("tile results from another rank are truncated");
        std::lock_guard tile_lock(tile_mutexes_[index]);
        for (int y = t.y0; y < t.y1; ++y, at += row_bytes) {
            std::memcpy(&image_.at(t.x0, y), bytes.data() + at, pixel_bytes);
            std::memcpy(refine_.data() + static_cast<std::size_t>(y) * image_.width + t.x0, bytes.data() + at + pixel_bytes,
                        width);
            for (std::size_t l = 0; l < layer_count; ++l)
                std::memcpy(&(*layers)[l].image->at(t.x0, y), bytes.data() + at + pixel_bytes + width + l * pixel_bytes,
                            pixel_bytes);
        }
        tile_versions_[index].store(++version_counter_, std::memory_order_release);
        tiles_done_.fetch_add(1, std::memory_order_relaxed);
    }
}

void RenderSession::render_distributed_classic(PassRunner& runner, TileContext& context) {
    // The classic passes with rank 0 handing out batches of tiles as ranks ask for them; every
    // pixel's samples come from its own random stream, so the image is one process's.
    const int width = job_.width, height = job_.height;
    refine_.assign(static_cast<std::size_t>(width) * height, 0);
    context.refine = &refine_;
    const bool antialias = has_antialiasing_pass(context);
    {
        std::lock_guard lock(mutex_);
        progress_.passes = antialias ? 2 : 1;
        progress_.tiles_total = tiles_.size() * progress_.passes;
    }
    const int tiles = static_cast<int>(tiles_.size());
    const int batch = std::max(1, 4 * tbb::this_task_arena::max_concurrency());
    auto share = [&](const char* name, int pass, auto&& body) {
        set_stage(name);
        {
            std::lock_guard lock(mutex_);
            progress_.pass = pass;
        }
        const double t0 = now_seconds();
        cluster_->checkpoint(nullptr, &cancel_requested_);
        const Cluster::WorkFn work = [&](int first, int last) {
            runner.run_range(first, last, body);
            if (cancel_requested_) throw ClusterError(RankFailure{cluster_->rank(), cluster_interrupted_code, "interrupted"});
            return tile_bytes(first, last, context.layers);
        };
        const Cluster::CollectFn collect = [&](int first, int last, const Cluster::Bytes& bytes) {
            put_tile_bytes(first, last, bytes, context.layers);
        };
        if (const std::optional<RankFailure> failure = cluster_->share_work(tiles, batch, work, collect, &cancel_requested_))
            throw ClusterError(*failure);
        std::lock_guard lock(mutex_);
        add_stage_time(name, now_seconds() - t0);
    };
    share("first samples", 0, [&](std::size_t, const Tile& tile, RayCounters& c) {
        render_first_pass_tile(context, tile, image_, c);
    });
    if (!antialias) return;
    // The anti-aliasing pass reads the whole first pass (and corner_grid's flags): rank 0 has it.
    // (Every buffer is made before the checkpoint: nothing may fail between it and the broadcast.)
    // The --layers images' first pass too: a layer's anti-aliased pixel starts from it.
    const std::size_t pixels = static_cast<std::size_t>(width) * height, image_bytes = pixels * sizeof(glm::vec3);
    const std::size_t layer_count = context.layers ? context.layers->size() : 0;
    const std::size_t total = image_bytes * (1 + layer_count) + pixels;
    Cluster::Bytes first;
    std::exception_ptr error;
    try {
        first.reserve(total);
        if (cluster_->rank() == 0) {
            first.resize(total);
            std::memcpy(first.data(), image_.pixels.data(), image_bytes);
            std::memcpy(first.data() + image_bytes, refine_.data(), pixels);
            for (std::size_t l = 0; l < layer_count; ++l)
                std::memcpy(first.data() + image_bytes + pixels + l * image_bytes,
                            (*context.layers)[l].image->pixels.data(), image_bytes);
        }
    } catch (...) {
        error = std::current_exception();
    }
    cluster_->checkpoint(error, &cancel_requested_);
    cluster_->broadcast(first, 0);
    if (first.size() != total) throw std::runtime_error("the first pass from rank 0 has the wrong size");
    if (cluster_->rank() != 0) {
        std::memcpy(image_.pixels.data(), first.data(), image_bytes);
        std::memcpy(refine_.data(), first.data() + image_bytes, pixels);
        for (std::size_t l = 0; l < layer_count; ++l)
            std::memcpy((*context.layers)[l].image->pixels.data(), first.data() + image_bytes + pixels + l * image_bytes,
                        image_bytes);
    }
    first_pass_ = image_;
    share("anti-aliasing", 1, [&](std::size_t, const Tile& tile, RayCounters& c) {
        render_antialiasing_tile(context, tile, first_pass_, image_, c);
    });
}

}  // namespace caustica
