// A render session: the lifecycle every front end drives (STYLE.md 3 and 4).
//   set_job -> prepare (build what is stale) -> start (background) -> progress() -> cancel -> wait
// Stages are cached by what they depend on (core/render/fingerprints.h): the BVH by the geometry,
// the photons by that and the options that feed them. The session keeps the lifecycle, the stage
// cache, the threads, cancellation and tile publication; an integrator's own loop renders through
// a RenderHost (core/render/render_host.h). Its steps with other ranks are in session_cluster.cpp;
// the hover readout is core/render/scene_inspector.*.
// The batch command runs a session to completion; the preview app drives the same object.
#pragma once

#include "core/render/image.h"
#include "core/render/render_stats.h"
#include "core/photons/projection_map.h"
#include "core/geometry/ray.h"
#include "core/scene/scene_desc.h"
#include "core/render/tile_renderer.h"
#include "core/integrators/progressive_accumulator.h"
#include "core/render/render_host.h"
#include "core/render/scene_inspector.h"
#include "core/render/cluster.h"
#include "core/render/fingerprints.h"
#include "core/render/render_layers.h"

#include <tbb/task_arena.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace caustica {

class RenderScene;
class TextureSet;
struct CausticStage;

/// A light's projection map and where the light is, for overlays.
struct LightProjectionMap {
    ProjectionMap map;
    glm::vec3 light_position;
    int light_index;  ///< position in the job's light list
};

/// A consistent view of how far the current render is.
struct SessionProgress {
    std::uint64_t generation = 0;  ///< increments with every start()
    int pass = 0;                  ///< 0 = first samples, 1 = anti-aliasing
    int passes = 1;
    std::size_t tiles_done = 0, tiles_total = 0;  ///< over all passes
    double elapsed_seconds = 0.0;
    bool running = false;
    bool finished = false;   ///< completed every pass
    bool cancelled = false;
    /// Every stage before the image passes (scene, photons) is built without error. A preview may
    /// show a direct-light pass before that (its tiles do not mean the job renders).
    bool prepared = false;
    /// The image holds a coarse direct-light pass (no photon terms) while the photons of this render
    /// are shot; false again once its photon stage is done.
    bool showing_direct_light = false;
    std::string stage;       ///< what is being done now
    /// Progressive accumulation (Options::accumulates()): passes averaged so far, their limit
    /// (0 = none), photon directions over all passes, mean samples per pixel, the radius of the
    /// last pass and the estimated relative error (ErrorEstimate::known false until 2 passes).
    bool accumulating = false;
    int passes_done = 0, pass_limit = 0;
    long long photons_emitted = 0;
    double samples_per_pixel = 0.0;
    double radius = 0.0;
    double accumulated_seconds = 0.0;  ///< rendering time of the accumulation over every start and resume
    ErrorEstimate error;
    /// The photon stage of the current pass: directions considered so far, of how many.
    long long photons_done = 0, photons_total = 0;
    std::string stopped_by;  ///< why accumulation stopped: "passes", "time", "target error", "cancelled"
};

/// A progressive accumulation taken out of a session to be continued later (the preview keeps the
/// last one a change restarted, so that undoing the change brings its passes back): the job it
/// renders, the integrator's loop holding its sums, counts, radii and seeds, and its image.
struct KeptAccumulation {
    RenderJob job;
    std::unique_ptr<RenderLoop> loop;
    IntegratorKind kind = IntegratorKind::progressive;  ///< the integrator the loop belongs to
    Image image;
};

/// Tile edge length in pixels.
inline constexpr int tile_size = 16;
/// Default block edge of the coarse preview pass (divides tile_size).
inline constexpr int preview_block = 4;

class RenderSession {
public:
    RenderSession();
    ~RenderSession();
    RenderSession(const RenderSession&) = delete;
    RenderSession& operator=(const RenderSession&) = delete;

    /// Sets what to render. Cheap: marks stale only the stages whose inputs changed.
    /// Cancels and waits for a render in progress.
    void set_job(const RenderJob& job);

    /// Builds the stale stages synchronously (flattening, BVH, photon maps). Throws InputError on
    /// scene errors. With a cluster of several ranks, every rank must call it (the classic photons
    /// are shared).
    void prepare();

    /// Builds the scene alone (flattening, BVH: what pick() needs), synchronously; cached like
    /// prepare()'s. Never talks to other ranks. Throws InputError on scene errors.
    void prepare_geometry();

    /// Starts rendering on the background thread pool (preparing first if needed); returns at once.
    void start();

    /// Progressive accumulation: continues the accumulation the last render stopped (a pause or
    /// a stopping rule), with the same job, until its stopping rules (see set_stop_rules) say
    /// otherwise. Returns false (and does nothing) when there is nothing to continue: another job
    /// was set since, or the job does not accumulate.
    bool resume();

    /// Progressive accumulation, saved for another run (docs/OUTPUT.md, "Resuming an
    /// accumulation"): the state the last render left, keyed by the current job; false when there
    /// is none (another job was set since, or it does not accumulate alone). Not while running.
    bool accumulation_state(AccumulationState& out) const;

    /// Starts rendering from a saved accumulation of the current job (set_job first), continuing
    /// it as resume() continues a paused one. Throws InputError with the reason when the state
    /// belongs to another job, or the job does not accumulate.
    void start_from(AccumulationState state);

    /// While accumulating: asks for a copy of the state at the end of the next whole pass, which
    /// take_accumulation_snapshot returns (keyed by the job) once made.
    void request_accumulation_snapshot();
    bool take_accumulation_snapshot(AccumulationState& out);

    /// Takes the stopped accumulation out of the session (the next job starts from nothing), to be
    /// given back with restore_accumulation; null when there is none that resume() could continue.
    /// Cancels and waits for a render in progress.
    std::unique_ptr<KeptAccumulation> take_accumulation();

    /// Sets `job`, which renders what kept->job renders (only its stopping rules and threads may
    /// differ), and puts the kept accumulation back: its image is published at once and resume()
    /// continues it from its pass count. False (and the job set, nothing to resume) when `kept`
    /// does not fit the job's integrator or image size.
    bool restore_accumulation(std::unique_ptr<KeptAccumulation> kept, const RenderJob& job);

    /// Changes the progressive stopping rules (--passes, --time, --target-error) of the job
    /// without restarting its accumulation; they take effect at the next start or resume.
    void set_stop_rules(int passes, double time_limit, double target_error);

    /// Renders only the pixels of `region` (clamped to the image; empty: every pixel) from the next
    /// start or resume on; every other pixel keeps what it holds (docs/PREVIEW.md, "Render
    /// region"). Never restarts an accumulation: its pixels keep their passes, and resume()
    /// continues it in the new region. Cancels and waits for a render in progress. Alone only: a
    /// session with other ranks renders every pixel.
    void set_region(const RenderRegion& region);
    /// The region set (empty: none).
    const RenderRegion& region() const { return region_; }

    /// Asks the running render to stop; tiles not yet started are dropped. Returns at once.
    void cancel();

    /// Waits for the background render. Returns true if it completed, false if cancelled.
    /// Rethrows an error raised while preparing or rendering.
    bool wait();
    /// Waits until the render has ended (completed, cancelled or failed) or `seconds` have
    /// passed, whichever comes first; returns whether it has ended (wait() then returns at once).
    /// A front end's progress loop waits here instead of sleeping, so it sees the end at once.
    bool wait_for_end(double seconds) const;

    /// Thread-safe snapshot of the progress.
    SessionProgress progress() const;

    /// The image; complete once wait() returned true. Tiles may be mid-render while running.
    const Image& image() const { return image_; }

    /// --layers: the image's light split into layers (docs/OUTPUT.md, "Layers"), complete once
    /// wait() returned true; empty without --layers, and for what renders no tile passes of its
    /// own (a progressive accumulation, several ranks).
    const std::vector<LayerImage>& layers() const { return layers_; }

    /// Copies into `out` the tiles published since the versions in `seen` (one per tile, updated),
    /// resizing `out` when the image size changed. Never waits for a tile being rendered. Call it
    /// from the thread that calls start(). Returns how many tiles were copied.
    std::size_t fetch_tiles(Image& out, std::vector<std::uint64_t>& seen) const;

    /// The first surface point along a ray in the last built scene (thread-safe; for picking).
    bool pick(const Ray& ray, glm::vec3& point) const;

    /// What `ray` meets first in the last built scene: point, node, material and the caustic
    /// photon map's radiance estimate there with the N and maximum distance of `options` (the
    /// shown job's), from the last built caustic map. One ray and one k-nearest query; thread-safe
    /// (the scene and its node index are shared snapshots, the map is read under the mutex).
    std::optional<SurfaceInspection> inspect(const Ray& ray, const Options& options) const;

    /// Copies of the projection maps of the last photon pass, with their lights (published as
    /// soon as the pass is done; empty when no map was built). Thread-safe.
    std::vector<LightProjectionMap> projection_maps() const;

    /// Renders a coarse preview pass (one sample per `block` x `block` square; block divides
    /// tile_size) before the full passes.
    void set_coarse_preview(bool on, int block = preview_block) {
        coarse_preview_ = on;
        preview_block_ = block > 0 && tile_size % block == 0 ? block : preview_block;
    }

    /// Whether photon lookups are wanted beyond what the job itself needs (the preview's coarse
    /// pass, readouts and photon dots): off, an accumulating progressive job's first photon pass
    /// builds no k-d tree (its passes gather from their own grid), which a batch render that
    /// never looks photons up saves. On by default.
    void set_photon_lookups(bool on) { photon_lookups_ = on; }

    /// Renders each job together with the other ranks of `cluster` (docs/SCALING.md; null or one
    /// rank: alone). Every rank's session must be given the same jobs in the same order and run
    /// them to the end (batch rendering: no resume). Rank 0's image is the one a single process
    /// makes from the same seeds; the other ranks' images are partial. A failure on any rank fails
    /// every rank with that rank's message (ClusterError from wait()); an interruption on any rank
    /// interrupts every rank.
    void set_cluster(Cluster* cluster) { cluster_ = cluster; }

    /// The tiles of the current image.
    const std::vector<Tile>& tiles() const { return tiles_; }

    /// Statistics of the last completed (or cancelled) render.
    RenderStats stats() const;

    /// Warnings found while preparing (e.g. nodes without material).
    std::vector<std::string> warnings() const;

    /// How many times each stage has actually been computed (for tests of caching).
    struct StageCounters {
        int scene_builds = 0;
        int photon_passes = 0;
        int renders = 0;
    };
    StageCounters stage_counters() const;

private:
    struct PassRunner;
    class Host;                 // the RenderHost a render loop sees
    void run();                 // the background thread's body
    void run_distributed(tbb::task_arena& arena, int threads);  // run() with the other ranks
    bool distributed() const { return cluster_ && cluster_->size() > 1; }
    void render_distributed_classic(PassRunner& runner, TileContext& context);
    /// Tiles [first, last) as another rank sends them: each row's pixels, refine flags and the
    /// --layers images' pixels (context.layers, or none).
    Cluster::Bytes tile_bytes(int first, int last, const std::vector<LayerTarget>* layers) const;
    void put_tile_bytes(int first, int last, const Cluster::Bytes& bytes, const std::vector<LayerTarget>* layers);
    void prepare_scene();       // flattening, BVH, textures
    void prepare_checked_scene();  // the job validated, its scene built, its option warnings
    void prepare_caustics();    // projection maps, photons, k-d tree (when lookups are needed)
    void publish_caustic_stats();  // under mutex_
    void make_image(int width, int height);  // the image and its tiles, at that size
    void render_passes(tbb::task_arena& arena, int threads);  // both image passes
    ShadingSetup make_setup() const;  // everything the integrator needs but the photon maps
    void render_direct_preview(tbb::task_arena& arena);  // a coarse direct-light pass before photons are shot
    RenderRegion region_in_image() const;  // region_ within the job's image; empty with other ranks
    void set_stage(const char* name);
    void add_stage_time(const std::string& name, double seconds);  // under mutex_
    void warn_once(const std::string& warning);
    void warn_about_options();  // options the job's integrator ignores

    RenderJob job_;
    std::uint64_t geometry_key_ = 0;        // fingerprint of what the BVH depends on
    std::uint64_t built_geometry_key_ = 0;
    std::uint64_t caustic_key_ = 0;         // fingerprint of what the photon map depends on, 0 = none
    std::shared_ptr<CausticStage> caustics_;  // replaced whole under mutex_, never changed after: inspect() keeps one
    std::shared_ptr<const RenderScene> scene_;  // replaced under mutex_ (pick reads it)
    std::shared_ptr<const RenderJob> inspect_job_;  // the job scene_ was built from, replaced with it under mutex_
    SceneInspector inspector_;  // inspect(): its node index of the built scene
    std::unique_ptr<TextureSet> textures_;
    std::vector<std::string> warnings_;

    Image image_, first_pass_;
    std::vector<LayerImage> layers_;  // --layers: those of the last complete tile passes
    std::vector<std::uint8_t> refine_;  // corner_grid: pixels the anti-aliasing pass refines
    // The progressive integrator's loop, kept across start()s so that resume() continues it.
    std::unique_ptr<RenderLoop> loop_;  // the job's integrator's own loop (null: the tile passes)
    IntegratorKind loop_kind_ = IntegratorKind::classic;  // the integrator loop_ was made for
    bool resuming_ = false;
    bool direct_first_ = false;  // this render showed a direct-light preview before its photons
    std::atomic<long long> photon_progress_{0};
    std::vector<Tile> tiles_;
    std::unique_ptr<std::mutex[]> tile_mutexes_;
    std::unique_ptr<std::atomic<std::uint64_t>[]> tile_versions_;
    std::atomic<std::uint64_t> version_counter_{0};
    bool coarse_preview_ = false;
    bool photon_lookups_ = true;
    /// Whether this job's photon stage must answer lookups (PhotonStageInputs::lookups): always for
    /// a single k-nearest pass and for photon dots. Asked when the stage is prepared: the stop
    /// rules and set_photon_lookups may change it after set_job.
    bool photon_lookups_needed() const {
        return photon_lookups_ || !job_.options.accumulates() || job_.options.draw_caustic_map;
    }
    /// The key of the photon stage the job needs: its fingerprint, told apart when the stage
    /// answers no lookups, so that neither kind is ever taken for the other (never 0 then).
    std::uint64_t stage_key() const;
    int preview_block_ = preview_block;
    RenderRegion region_;  // set_region(): the pixels the passes render (empty: all)
    std::thread worker_;
    std::atomic<bool> cancel_requested_{false};
    std::atomic<bool> running_{false};
    Cluster* cluster_ = nullptr;
    std::exception_ptr error_;

    mutable std::mutex mutex_;  // guards the fields below
    mutable std::condition_variable ended_;  // notified when progress_.running turns false
    SessionProgress progress_;
    RenderStats stats_;
    StageCounters counters_;
    std::atomic<std::size_t> tiles_done_{0};
    std::uint64_t generation_ = 0;
    double start_time_ = 0.0;
};

}  // namespace caustica
