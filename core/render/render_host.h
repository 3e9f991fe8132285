// What an integrator's own render loop needs from the session that runs it: the job and the
// stages the session built and caches, the image with its tiles and how they are published to a
// viewer, the cancel flag, the other ranks, and the progress and statistics a front end reads.
// The session keeps the lifecycle (set_job, start, cancel, resume, wait); a loop such as the
// progressive integrator's (core/integrators/progressive_render.*) decides what each pass does.
#pragma once

#include "core/render/accumulation_state.h"
#include "core/render/cluster.h"
#include "core/render/image.h"
#include "core/render/layer_image.h"
#include "core/render/render_stats.h"
#include "core/render/tile_renderer.h"
#include "core/scene/scene_desc.h"

#include <atomic>
#include <cstddef>
#include <functional>
#include <vector>

namespace caustica {

class RenderScene;
struct CausticStage;
struct SessionProgress;
struct ShadingSetup;

class RenderHost {
public:
    /// A tile's work: its index, its rectangle and the calling thread's counters.
    using TileBody = std::function<void(std::size_t, const Tile&, RayCounters&)>;

    virtual ~RenderHost() = default;

    /// The job being rendered (its size already resolved).
    virtual const RenderJob& job() const = 0;
    /// The built scene.
    virtual const RenderScene& scene() const = 0;
    /// The cached photon stage of the job (the first pass's photons), null when it has none.
    virtual const CausticStage* photon_stage() const = 0;
    /// Set by cancel(), or by Ctrl-C in the batch command.
    virtual const std::atomic<bool>& cancel_flag() const = 0;
    /// The ranks rendering this job together; null when alone.
    virtual Cluster* cluster() const = 0;
    /// Seconds since this render was started (steady clock).
    virtual double elapsed_seconds() const = 0;

    /// A coarse pass should be shown before the first full one (the preview's fast first image),
    /// one sample per block x block square; 0 when not wanted (batch, or already shown).
    virtual int coarse_preview_block() const = 0;
    /// A coarse direct-light image was shown before the photons were shot (it counts as a pass).
    virtual bool direct_preview_shown() const = 0;
    /// Whether --layers are rendered: in batch; never in the preview, which shows no layers.
    virtual bool renders_layers() const { return true; }

    /// The image the viewer copies tiles from, and its tiles.
    virtual Image& image() = 0;
    virtual const std::vector<Tile>& tiles() const = 0;
    /// The pixels the passes render, within the image (empty: all); the others keep their pixels
    /// and, in an accumulation, their sums. The error estimate and its stopping rule look at
    /// these pixels alone.
    virtual RenderRegion region() const = 0;
    /// Runs `body` on every tile on the session's threads, each under its tile's lock and then
    /// published (a viewer never sees a tile half-written); stops handing out tiles on cancel, and
    /// publishes none that ends after it (TileContext::cancel: it may have stopped half-way).
    /// `stage` names what -t reports and the progress shows; `pass` is the progress's pass number.
    virtual void run_tiles(const char* stage, int pass, const TileBody& body) = 0;
    /// Writes every tile with `fill` under its lock and publishes it (no threads).
    virtual void publish_tiles(const std::function<void(const Tile&)>& fill) = 0;
    /// The rays the tile bodies counted so far in this render.
    virtual RayCounters ray_totals() const = 0;

    /// Changes the progress and statistics a front end reads, under their lock.
    virtual void report(const std::function<void(SessionProgress&, RenderStats&)>& update) = 0;
    /// Adds a stage time (-t); repeated stages of a loop add up.
    virtual void add_stage_time(const char* stage, double seconds) = 0;
    /// Names what is being done now (the progress's stage).
    virtual void set_stage(const char* stage) = 0;
    /// Counts photon directions considered by the pass being shot (for progress reports).
    virtual std::atomic<long long>& photon_progress() = 0;
};

/// An integrator's own render loop, made by its registry entry (core/integrators/registry.h) for a
/// job that accumulates passes; without one the session renders its tile passes. The session keeps
/// the loop between renders, so that resume() continues what it holds.
class RenderLoop {
public:
    virtual ~RenderLoop() = default;
    /// Whether the loop holds work of the job last rendered that a resume may continue.
    virtual bool resumable() const = 0;
    /// Forgets that work (another job, or a fresh start).
    virtual void invalidate() = 0;
    /// Renders until a stopping rule or a cancel, continuing the held work when resumable.
    /// `setup` holds the scene-wide shading inputs; `context` the camera and the base seed.
    virtual void run(RenderHost& host, const ShadingSetup& setup, const TileContext& context) = 0;

    // Saving the held work for another run (docs/OUTPUT.md, "Resuming an accumulation"). A loop
    // that cannot save keeps these defaults; `key` of a state is the caller's to fill and check.
    /// Copies the held work into `out` between renders; false when it holds none.
    virtual bool save_state(AccumulationState& /*out*/) const { return false; }
    /// Takes up saved work of the current job, continued by the next resumed run; false (holding
    /// nothing) when it does not fit the loop.
    virtual bool restore_state(AccumulationState&& /*state*/) { return false; }
    /// While running: asks for a copy of the work as it stands at the end of the next whole pass.
    virtual void request_snapshot() {}
    /// The copy asked for, once made (moved out); false until then.
    virtual bool take_snapshot(AccumulationState& /*out*/) { return false; }

    /// --layers: the layers of the held work (docs/OUTPUT.md, "Layers"), in written_layers order;
    /// empty when the loop renders none or did not render them over all of its work.
    virtual std::vector<LayerImage> layer_images() const { return {}; }
};

}  // namespace caustica
