// Drives a RenderSession for an interactive view without ever waiting for it: a new job cancels
// the running render and starts once the worker has stopped (a few milliseconds), tiles are
// copied as they are published, and results (errors, projection maps, stage times) are collected
// when a render ends. A progressive accumulation can be paused and resumed, and its stopping
// rules changed, without starting it again. Everything here runs on the UI thread; nothing here
// knows about GL.
#pragma once

#include "core/render/accumulation_state.h"
#include "core/render/render_session.h"

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace caustica::ui {

/// One completed image pass, for the time-per-pass plot.
struct PassTime {
    std::uint64_t generation = 0;
    std::string name;  ///< "preview", "first samples", "anti-aliasing", "progressive pass"
    double seconds = 0.0;
};

/// When a progressive accumulation stops (Options::passes, time_limit, target_error).
struct StopRules {
    int passes = 0;             ///< pass limit, 0 = none
    double time_limit = 0.0;    ///< seconds of rendering, 0 = none
    double target_error = 0.0;  ///< estimated relative error, 0 = none

    /// The rules of a job's options, and writing them back.
    static StopRules of(const Options& options) {
        return {options.pass_limit(), options.time_limit, options.target_error};
    }
    void apply(Options& options) const {
        options.passes = passes;
        options.passes_given = true;
        options.time_limit = time_limit;
        options.target_error = target_error;
    }
    bool operator==(const StopRules&) const = default;
};

/// Tuning of the restart policy.
struct DriverSettings {
    bool coarse_preview = true;            ///< coarse pass before the full passes
    /// Edge of the coarse pass's blocks: 8 x 8 samples 1/64 of the pixels, so the first view of a
    /// camera move keeps up even while software GL shares the two cores (docs/PERFORMANCE.md).
    int preview_block = 8;
    double max_preview_wait_seconds = 0.1; ///< a render younger than this finishes its preview before a newer job replaces it
    double cancel_spin_seconds = 0.004;    ///< how long update() may wait for a cancelled worker before retrying next frame
    /// An accumulation that has run this many passes, or this many seconds, is kept when a change
    /// restarts it (docs/PREVIEW.md, "Progressive refinement").
    int keep_after_passes = 8;
    double keep_after_seconds = 5.0;
};

/// The non-blocking front of a RenderSession.
class PreviewDriver {
public:
    explicit PreviewDriver(DriverSettings settings = {});

    /// Asks for `job` to be rendered next (the newest request wins). A request made while paused
    /// ends the pause: the new job is rendered.
    void request(const RenderJob& job);

    /// What became of a saved accumulation handed to request_continuing, once its job started.
    struct SavedStart {
        int passes = 0;       ///< the passes it held
        std::string refusal;  ///< why the session refused it ("" = continued)
    };
    /// Asks for `job` as request() does, continuing `saved`, an accumulation of that job read from
    /// its file (docs/OUTPUT.md, "Resuming an accumulation"), unless the accumulation kept aside
    /// continues it (kept_passes). take_saved_start() says what became of it.
    void request_continuing(const RenderJob& job, AccumulationState saved);
    /// What became of the last saved accumulation handed over, once (nothing: not started yet,
    /// replaced by a newer request, or the accumulation kept aside went on instead).
    std::optional<SavedStart> take_saved_start();

    /// Stops the running render, keeping what a progressive accumulation has gathered; the image
    /// stays as it is. Does nothing when no render is running.
    void pause();
    /// Continues the paused render: an accumulation from its pass count, any other render (or an
    /// accumulation paused before its first pass) from the start.
    void resume();
    /// The passes of the accumulation kept aside (0: none). A job that restarts an accumulation of
    /// keep_after_passes or keep_after_seconds keeps it (at most one, the one with more passes)
    /// until a fresh accumulation has more passes or another scene opens; requesting its job again
    /// (the change undone, the camera back) continues it from its passes, and keeps the one it
    /// replaces in its turn.
    int kept_passes() const { return kept_ ? kept_progress_.passes_done : 0; }

    /// Whether the preview is paused.
    bool paused() const { return paused_; }
    /// Changes the stopping rules of the progressive accumulation without starting it again: the
    /// running render stops and continues under the new rules (an accumulation that has stopped
    /// continues too, when the new rules allow more passes). Nothing else is rendered again.
    void set_stop_rules(const StopRules& rules);
    /// Renders only the pixels of `region` from now on (empty: the whole image), the others
    /// keeping what they show (docs/PREVIEW.md, "Render region"). Like new stopping rules, it
    /// never starts an accumulation again: the running render stops and continues in the region
    /// (a paused one when resumed); a render that does not accumulate renders the region again.
    void set_region(const RenderRegion& region);
    /// The region asked for (empty: none).
    const RenderRegion& region() const { return region_; }

    /// The per-frame step: restarts when due, copies new tiles, collects ended renders. Never
    /// waits for a tile; may wait up to cancel_spin_seconds for a cancelled worker to stop.
    void update();

    /// Between frames: starts a requested job as soon as the cancelled worker has stopped (no
    /// tile copying, no waiting), so that a restart need not wait for the next frame.
    void poll();

    /// The image as shown. Tiles are copied only from the newest render started: its last tiles
    /// just before the next one starts, then only the next one's, so no older tile ever appears.
    const Image& image() const { return image_; }
    /// Indices (into tiles()) of the tiles the last update() copied.
    const std::vector<std::size_t>& changed_tiles() const { return changed_; }
    /// For each changed tile, the generation (SessionProgress::generation) of the render it came from.
    const std::vector<std::uint64_t>& changed_generations() const { return changed_generations_; }
    /// The generation of the newest render started.
    std::uint64_t generation() const { return generation_; }
    /// Whether the last update() changed the image size (every tile is then new).
    bool size_changed() const { return size_changed_; }
    /// The tile rectangles of the current image.
    const std::vector<Tile>& tiles() const { return session_.tiles(); }

    /// The progress snapshot taken by the last update().
    const SessionProgress& progress() const { return progress_; }
    /// The last snapshot of the progressive accumulation shown (passes, photons, error, radius):
    /// kept across a pause and resume, reset when another job starts. `accumulating` is false
    /// before the first pass of a job that accumulates, and for jobs that do not.
    const SessionProgress& accumulation() const { return accumulation_; }
    /// Whether a job has been started.
    bool has_job() const { return started_; }
    /// The job of the current (last started) render.
    const RenderJob& job() const { return job_; }
    /// Whether a requested job waits for the running render to stop.
    bool pending() const { return pending_.has_value(); }
    /// Whether the current render has completed its first full-resolution pass (and nothing is
    /// pending); for an accumulation, its first progressive pass.
    bool first_full_pass_done() const;
    /// Whether the current render completed every pass (and nothing is pending); an accumulation
    /// only finishes on a stopping rule (a pause is not an end).
    bool finished() const { return !pending_ && started_ && collected_ && progress_.finished; }
    /// Whether the photon maps of the current job are final (projection_maps() shows them): the
    /// render finished, or an accumulation has completed its first pass (later passes' photons
    /// are not kept).
    bool maps_final() const;
    /// Whether the current render is between start and collection.
    bool busy() const { return started_ && !collected_; }

    /// Forgets what belongs to the previous scene (statistics, stage and pass times, projection
    /// maps) when another scene is opened: its numbers never show for the new one.
    void forget_scene();

    /// The error of the last render that failed (scene errors found while preparing), once.
    std::optional<std::string> take_error();

    /// Projection maps of the last finished render with a photon pass.
    const std::vector<LightProjectionMap>& projection_maps() const { return maps_; }
    /// Increments whenever projection_maps() changes content.
    std::uint64_t maps_version() const { return maps_version_; }

    /// Stage times and counters, refreshed a few times a second and when a render ends.
    const RenderStats& stats() const { return stats_; }
    /// Completed passes, oldest first (at most 240).
    const std::deque<PassTime>& pass_history() const { return pass_history_; }
    /// Times of the last real (not cached) computation of each preparation stage, by name.
    const std::vector<StageTime>& computed_stages() const { return computed_stages_; }

    /// The longest time a restart (set_job + start, which join the stopped worker) took so far.
    /// A restart that changes the image size allocates it (milliseconds at 1280 x 720).
    double longest_restart_seconds() const { return longest_restart_; }
    /// The time the last restart took.
    double last_restart_seconds() const { return last_restart_; }
    /// How many renders have been started.
    std::uint64_t restarts() const { return restarts_; }

    /// The session (for pick and stage_counters, which are thread-safe).
    RenderSession& session() { return session_; }
    const RenderSession& session() const { return session_; }

private:
    void advance(bool spin);  // the restart policy: cancel when due, collect, restart or resume
    void take_progress();  // progress_ and accumulation_ from the session, progressive pass times
    void record_pass(const std::string& name, double seconds);  // into pass_history_
    void collect();   // the worker has stopped: error, stats, maps, pass times
    void restart();   // start the pending job
    void continue_accumulation();  // resume the stopped render (or start it again)
    void apply_stop_rules();  // the worker has stopped: the new rules, then continue
    void apply_region();      // the worker has stopped: the new region (advance() continues)
    void fetch();     // copy the tiles the newest render published since the last copy
    void refresh_maps();
    void poll_stats();  // stats_ and computed_stages_ from the session
    std::optional<SessionProgress> restore_kept_accumulation();  // job_ comes back: its kept passes continue
    bool worth_keeping(const SessionProgress& accumulation) const;  // keep_after_passes or _seconds
    void keep_accumulation();      // before a new job: the stopped accumulation, when worth keeping
    void drop_overtaken_accumulation();  // the kept one, once a fresh accumulation has more passes
    bool start_saved_accumulation(AccumulationState saved);  // after set_job: false when the session refuses it

    DriverSettings settings_;
    RenderSession session_;
    RenderJob job_;
    std::optional<RenderJob> pending_;
    bool started_ = false, collected_ = true, cancel_sent_ = false;
    bool paused_ = false, resume_due_ = false, maps_refreshed_ = false;
    bool stats_forgotten_ = false;  // forget_scene(): no statistics until the next render starts
    std::optional<StopRules> new_rules_;
    RenderRegion region_;
    bool new_region_ = false;  // region_ has not reached the session yet
    std::unique_ptr<KeptAccumulation> kept_;  // the one accumulation kept aside (preview_driver_keep.cpp)
    SessionProgress kept_progress_;           // what it showed
    bool kept_overtakable_ = false;           // a fresh accumulation runs since it was kept
    std::optional<AccumulationState> pending_saved_;  // read from a file, for the pending job
    std::optional<SavedStart> saved_start_;
    double started_at_ = 0.0, stats_polled_at_ = 0.0;
    double pass_clock_ = 0.0;  // when the accumulation's pass count last changed (or it started)
    std::uint64_t clock_generation_ = 0;  // the render pass_clock_ belongs to
    SessionProgress progress_, accumulation_;

    Image image_;
    std::vector<std::uint64_t> seen_, previous_seen_;
    std::vector<std::size_t> changed_;
    std::vector<std::uint64_t> changed_generations_;
    std::uint64_t generation_ = 0;
    std::size_t reported_ = 0;  // changed tiles the last update() reported
    bool size_changed_ = false;

    std::optional<std::string> error_;
    std::vector<LightProjectionMap> maps_;
    std::uint64_t maps_version_ = 0;
    RenderStats stats_;
    std::deque<PassTime> pass_history_;
    std::vector<StageTime> computed_stages_;
    double longest_restart_ = 0.0, last_restart_ = 0.0;
    std::uint64_t restarts_ = 0;
};

/// Why an accumulation stopped (SessionProgress::stopped_by), in words: "the pass limit", ...
std::string stop_reason(const std::string& stopped_by);

/// What a running render does, in words: its stage, "refining" for progressive passes, and
/// "direct light; shooting photons" while a direct-light pass stands in for the image.
std::string running_stage(const SessionProgress& progress);

/// How far a render is, 0 to 1: during its photon stage, the photon directions shot (0 while the
/// stage does not count them); else the tiles of its image passes.
double render_fraction(const SessionProgress& progress);

/// Whether two projection maps have the same cells and light.
bool same_projection_maps(const std::vector<LightProjectionMap>& a, const std::vector<LightProjectionMap>& b);

}  // namespace caustica::ui
