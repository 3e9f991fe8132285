// Internal to RenderSession (core/render/render_session*.cpp): the steady clock it times stages
// with, and PassRunner, which runs a body over the session's tiles on its threads and publishes
// each tile as it is done.
#pragma once

#include "core/render/render_session.h"
#include "core/util/denormals.h"
#include "core/util/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/task_arena.h>

#include <chrono>

namespace caustica {

inline double now_seconds() {
    using clock = std::chrono::steady_clock;
    return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

struct RenderSession::PassRunner {
    RenderSession& session;
    tbb::task_arena& arena;
    tbb::enumerable_thread_specific<RayCounters> counters;

    template <typename Body>
    void run(const char* name, int pass, Body&& body) {
        session.set_stage(name);
        {
            std::lock_guard lock(session.mutex_);
            session.progress_.pass = pass;
        }
        const double t0 = now_seconds();
        const std::vector<Tile>& tiles = session.tiles_;
        arena.execute([&] {
            caustica::parallel_for(tbb::blocked_range<std::size_t>(0, tiles.size(), 1),
                              [&](const tbb::blocked_range<std::size_t>& range) {
                                  const ScopedFlushDenormals flush;
                                  for (std::size_t i = range.begin(); i != range.end(); ++i) {
                                      if (session.cancel_requested_.load(std::memory_order_relaxed)) return;
                                      {
                                          std::lock_guard tile_lock(session.tile_mutexes_[i]);
                                          body(i, tiles[i], counters.local());
                                          if (cut_short()) return;
                                          session.tile_versions_[i].store(++session.version_counter_,
                                                                          std::memory_order_release);
                                      }
                                      session.tiles_done_.fetch_add(1, std::memory_order_relaxed);
                                  }
                              });
        });
        std::lock_guard lock(session.mutex_);
        session.add_stage_time(name, now_seconds() - t0);
    }

    /// Runs `body` on tiles [first, last) (a batch another rank may have been given instead):
    /// published like run()'s, not counted as done (the rank that collects them counts them).
    template <typename Body>
    void run_range(int first, int last, Body&& body) {
        const std::vector<Tile>& tiles = session.tiles_;
        arena.execute([&] {
            caustica::parallel_for(tbb::blocked_range<int>(first, last, 1), [&](const tbb::blocked_range<int>& range) {
                const ScopedFlushDenormals flush;
                for (int i = range.begin(); i != range.end(); ++i) {
                    if (session.cancel_requested_.load(std::memory_order_relaxed)) return;
                    const std::size_t t = static_cast<std::size_t>(i);
                    std::lock_guard tile_lock(session.tile_mutexes_[t]);
                    body(t, tiles[t], counters.local());
                    if (cut_short()) return;
                    session.tile_versions_[t].store(++session.version_counter_, std::memory_order_release);
                }
            });
        });
    }

    /// Whether the tile body that just returned on this thread may have been cut short by a cancel
    /// (it stops between packets: TileContext::cancel). Such a tile is neither published nor
    /// counted: a viewer keeps the copy it has (docs/RELIABILITY.md, "Bounded time").
    bool cut_short() const { return session.cancel_requested_.load(std::memory_order_relaxed); }

    RayCounters total() const {
        RayCounters t;
        for (const RayCounters& c : counters) t += c;
        return t;
    }
};

}  // namespace caustica
