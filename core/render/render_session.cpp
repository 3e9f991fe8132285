#include "core/render/render_session.h"

#include "core/render/session_passes.h"

#include "core/scene/camera.h"
#include "core/photons/caustic_stage.h"
#include "core/util/denormals.h"
#include "core/integrators/registry.h"
#include "core/render/random.h"
#include "core/render/render_memory.h"
#include "core/geometry/render_scene.h"
#include "core/scene/scene_flatten.h"
#include "core/scene/scene_validate.h"
#include "core/scene/source_location.h"
#include "core/shading/texture.h"
#include "core/render/tile_renderer.h"
#include "core/util/radiance_range.h"
#include "core/geometry/shapes.h"
#include "core/util/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cstring>
#include <algorithm>
#include <functional>
#include <limits>
#include <new>
#include <random>

namespace caustica {

RenderSession::RenderSession() = default;

RenderSession::~RenderSession() {
    cancel();
    if (worker_.joinable()) worker_.join();
}

void RenderSession::set_job(const RenderJob& job) {
    cancel();
    if (worker_.joinable()) worker_.join();
    job_ = job;
    const int size = job_.options.resolution_override;
    if (size > 0) job_.width = job_.height = size;
    geometry_key_ = geometry_fingerprint(job_);
    caustic_key_ = caustics_needed(job_) ? caustic_fingerprint(job_, geometry_key_) : 0;
    const IntegratorEntry& integrator = integrator_entry(job_.options.integrator);
    if (!loop_ || loop_kind_ != integrator.kind) {
        loop_ = integrator.make_loop ? integrator.make_loop() : nullptr;
        loop_kind_ = integrator.kind;
    }
    if (loop_) loop_->invalidate();  // any change of job starts the accumulation again
}

std::uint64_t RenderSession::stage_key() const {
    if (caustic_key_ == 0 || photon_lookups_needed()) return caustic_key_;
    return hash_combine(caustic_key_, 0x6e6f2d6b64ULL) | 1;
}

void RenderSession::set_stop_rules(int passes, double time_limit, double target_error) {
    cancel();
    if (worker_.joinable()) worker_.join();
    job_.options.passes = passes;
    job_.options.passes_given = true;
    job_.options.time_limit = time_limit;
    job_.options.target_error = target_error;
}

void RenderSession::set_region(const RenderRegion& region) {
    cancel();
    if (worker_.joinable()) worker_.join();
    region_ = region;
}

RenderRegion RenderSession::region_in_image() const {
    return distributed() ? RenderRegion{} : clamp_region(region_, job_.width, job_.height);
}

bool RenderSession::resume() {
    cancel();
    if (worker_.joinable()) worker_.join();
    if (!loop_ || !loop_->resumable() || !job_.options.accumulates() || image_.width != job_.width ||
        image_.height != job_.height)
        return false;
    resuming_ = true;
    start();
    return true;
}

bool RenderSession::accumulation_state(AccumulationState& out) const {
    if (running_ || distributed() || !loop_ || !loop_->save_state(out)) return false;
    out.key = accumulation_key(job_);
    return true;
}

void RenderSession::start_from(AccumulationState state) {
    cancel();
    if (worker_.joinable()) worker_.join();
    if (!loop_ || !job_.options.accumulates() || distributed())
        throw InputError("a saved accumulation continues only a progressive render that accumulates passes, alone");
    if (const std::string mismatch = accumulation_mismatch(state.key, accumulation_key(job_)); !mismatch.empty())
        throw InputError("cannot continue the saved accumulation: " + mismatch);
    if (!loop_->restore_state(std::move(state))) throw InputError("the saved accumulation does not fit its image size");
    resuming_ = true;
    start();
}

void RenderSession::request_accumulation_snapshot() {
    if (loop_) loop_->request_snapshot();
}

bool RenderSession::take_accumulation_snapshot(AccumulationState& out) {
    if (!loop_ || !loop_->take_snapshot(out)) return false;
    out.key = accumulation_key(job_);
    return true;
}

void RenderSession::add_stage_time(const std::string& name, double seconds) {
    // The progressive passes are many: one line each for their photons and their images.
    if (name == "progressive passes" || name == "photon passes")
        for (StageTime& s : stats_.stages)
            if (s.name == name) {
                s.seconds += seconds;
                return;
            }
    stats_.stages.push_back({name, seconds, false});
}

void RenderSession::set_stage(const char* name) {
    std::lock_guard lock(mutex_);
    progress_.stage = name;
}

void RenderSession::warn_once(const std::string& warning) {
    std::lock_guard lock(mutex_);
    if (std::find(warnings_.begin(), warnings_.end(), warning) == warnings_.end()) warnings_.push_back(warning);
}

void RenderSession::warn_about_options() {
    const Options& o = job_.options;
    if (!integrator_entry(o.integrator).accumulates && (o.passes != 1 || o.time_limit > 0.0 || o.target_error > 0.0))
        warn_once("--passes, --time and --target-error need --integrator progressive: the classic integrator "
                  "renders its passes as the original did; ignored");
}

void RenderSession::prepare_checked_scene() {
    if (!job_.scene) throw InputError("no scene to render");
    validate_render_job(job_);  // numbers the renderer cannot compute with: refused with their line
    check_shown_layer(job_.options);
    prepare_scene();
    warn_about_options();
}

void RenderSession::prepare() {
    cancel_requested_ = false;  // set_job cancelled the last render, not this
    prepare_checked_scene();
    if (cancel_requested_) return;  // the photon pass would be thrown away
    prepare_caustics();
}

void RenderSession::prepare_geometry() {
    cancel_requested_ = false;
    prepare_checked_scene();
}

void RenderSession::prepare_scene() {
    if (scene_ && built_geometry_key_ == geometry_key_) {
        std::lock_guard lock(mutex_);
        stats_.stages.push_back({"scene build", 0.0, true});
        return;
    }
    set_stage("building the scene");
    const double t0 = now_seconds();
    FlatScene flat = flatten_scene(job_);
    validate_flat_scene(flat, *job_.scene);
    check_render_memory(job_, flat);  // refused before anything is built (docs/RELIABILITY.md, "Bounded memory")
    {
        std::lock_guard lock(mutex_);  // pick() may be reading the old scene from another thread
        scene_.reset();
    }
    textures_.reset();
    {
        std::lock_guard lock(mutex_);  // projection_maps() may be reading it
        caustics_ = std::make_unique<CausticStage>();  // depends on the geometry
    }
    std::shared_ptr<const RenderScene> scene;
    try {
        scene = std::make_shared<const RenderScene>(*job_.scene, flat, &cancel_requested_);
    } catch (const SceneBuildCancelled&) {
        return;  // nothing built: the next render builds the scene again
    }
    textures_ = std::make_unique<TextureSet>(*job_.scene);
    built_geometry_key_ = geometry_key_;
    auto built_job = std::make_shared<const RenderJob>(job_);  // inspect() indexes it on first use
    std::lock_guard lock(mutex_);
    scene_ = std::move(scene);
    inspect_job_ = std::move(built_job);
    warnings_ = std::move(flat.warnings);
    ++counters_.scene_builds;
    stats_.stages.push_back({"scene build", now_seconds() - t0, false});
    stats_.scene = scene_->info();
}

void RenderSession::prepare_caustics() {
    if (caustic_key_ == 0) {  // no photon pass: nothing specular, no photons, or disabled
        std::lock_guard lock(mutex_);
        caustics_ = std::make_unique<CausticStage>();
        publish_caustic_stats();
        return;
    }
    if (caustics_ && caustics_->key == stage_key()) {
        std::lock_guard lock(mutex_);
        stats_.stages.push_back({"photon pass", 0.0, true});
        publish_caustic_stats();
        return;
    }
    set_stage("shooting photons");
    auto fresh = std::make_unique<CausticStage>();
    photon_progress_ = 0;
    const IntegratorEntry& integrator = integrator_entry(job_.options.integrator);
    if (integrator.photon_directions) {  // it reports its progress
        std::lock_guard lock(mutex_);
        progress_.photons_total = integrator.photon_directions(job_);
    }
    PhotonStageInputs inputs;
    inputs.cancel = &cancel_requested_;
    inputs.textures = textures_.get();
    inputs.cluster = cluster_;  // the builder decides whether it has other ranks
    inputs.progress = &photon_progress_;
    inputs.lookups = photon_lookups_needed();
    integrator.build_photons(*fresh, *scene_, job_, inputs);
    fresh->key = cancel_requested_ ? 0 : stage_key();  // a cancelled pass is not reused
    std::lock_guard lock(mutex_);  // published at once: the preview shows maps and counts early
    caustics_ = std::move(fresh);
    ++counters_.photon_passes;
    stats_.stages.push_back({"projection maps", caustics_->map_seconds, false});
    stats_.stages.push_back({"photon shooting", caustics_->shoot_seconds, false});
    if (caustics_->map || caustics_->gi_map)  // (none for a stage without lookups)
        stats_.stages.push_back({"photon k-d tree", caustics_->tree_seconds, false});
    for (const std::string& w : caustics_->warnings) warnings_.push_back(w);
    publish_caustic_stats();
}

void RenderSession::publish_caustic_stats() {
    stats_.caustic_lights = caustics_->lights;
    // (A stage without lookups holds its photons as stored, without a tree.)
    stats_.caustic_photons = caustics_->map ? caustics_->map->size() : caustics_->photons.size();
    stats_.caustic_map_bytes = caustics_->map ? caustics_->map->memory_bytes() : caustics_->photons.size() * sizeof(Photon);
    stats_.gi_lights = caustics_->gi_lights;
    stats_.gi_photons = caustics_->gi_map ? caustics_->gi_map->size() : 0;
    stats_.gi_map_bytes = caustics_->gi_map ? caustics_->gi_map->memory_bytes() : 0;
}

void RenderSession::start() {
    cancel();
    if (worker_.joinable()) worker_.join();
    if (!resuming_ && loop_) loop_->invalidate();
    resuming_ = false;
    cancel_requested_ = false;
    error_ = nullptr;
    {
        std::lock_guard lock(mutex_);
        progress_ = SessionProgress{};
        progress_.generation = ++generation_;
        progress_.running = true;
        stats_.stages.clear();
        stats_.rays = {};
    }
    tiles_done_ = 0;
    // The image and its tiles are (re)made here, on the thread that also fetches tiles.
    if (image_.width != job_.width || image_.height != job_.height) make_image(job_.width, job_.height);
    start_time_ = now_seconds();
    running_ = true;
    worker_ = std::thread([this] { run(); });
}

void RenderSession::make_image(int width, int height) {
    image_ = Image(width, height);
    tiles_ = make_tiles(width, height, tile_size);
    tile_mutexes_ = std::make_unique<std::mutex[]>(tiles_.size());
    tile_versions_ = std::make_unique<std::atomic<std::uint64_t>[]>(tiles_.size());
    for (std::size_t i = 0; i < tiles_.size(); ++i) tile_versions_[i] = 0;
}

void RenderSession::run() {
    try {
        const int threads = job_.options.threads > 0 ? job_.options.threads : tbb::info::default_concurrency();
        tbb::task_arena arena(threads);
        // Flush-to-zero is set per task where rays are traced (tiles, photons, projection maps),
        // not here: validation must see the smallest numbers as they are.
        arena.execute([&] {
            if (distributed()) {
                run_distributed(arena, threads);
                return;
            }
            prepare_checked_scene();
            if (cancel_requested_) return;
            // A preview shows direct light at once, whichever the integrator: a coarse pass before
            // photons that are not cached yet are shot (docs/PREVIEW.md, "While photons are shot").
            // Batch renders have no coarse pass, so their images never depend on it.
            direct_first_ = coarse_preview_ && !(loop_ && loop_->resumable()) && caustic_key_ != 0 &&
                            !(caustics_ && caustics_->key == stage_key());
            if (direct_first_) render_direct_preview(arena);
            if (cancel_requested_) return;
            prepare_caustics();
            if (cancel_requested_) return;
            {
                std::lock_guard lock(mutex_);
                progress_.prepared = true;
                progress_.showing_direct_light = false;
            }
            render_passes(arena, threads);
        });
    } catch (const ClusterError& e) {
        if (e.interrupted())
            cancel_requested_ = true;  // another rank (or this one) was interrupted: every rank stops
        else
            error_ = std::current_exception();
    } catch (const InputError& e) {
        error_ = std::make_exception_ptr(job_.located_option_error(e));
    } catch (...) {
        error_ = std::current_exception();
    }
    {
        std::lock_guard lock(mutex_);
        progress_.running = false;
        progress_.cancelled = cancel_requested_.load();
        progress_.finished = !error_ && !progress_.cancelled;
        progress_.elapsed_seconds = now_seconds() - start_time_;
        stats_.total_seconds = progress_.elapsed_seconds;
        running_ = false;
    }
    ended_.notify_all();
}

void RenderSession::cancel() { cancel_requested_ = true; }

bool RenderSession::pick(const Ray& ray, glm::vec3& point) const {
    std::shared_ptr<const RenderScene> scene;
    {
        std::lock_guard lock(mutex_);
        scene = scene_;
    }
    SurfaceHit hit;
    if (!scene || !scene->intersect(ray, hit)) return false;
    point = hit.position;
    return true;
}

std::optional<SurfaceInspection> RenderSession::inspect(const Ray& ray, const Options& options) const {
    std::shared_ptr<const RenderScene> scene;
    std::shared_ptr<const RenderJob> job;
    std::shared_ptr<const CausticStage> stage;
    {
        std::lock_guard lock(mutex_);  // all three are replaced whole under it; the query runs outside
        scene = scene_;
        job = inspect_job_;
        stage = caustics_;
    }
    return inspector_.inspect(scene, job, stage, ray, options);
}

std::vector<LightProjectionMap> RenderSession::projection_maps() const {
    std::lock_guard lock(mutex_);
    std::vector<LightProjectionMap> maps;
    if (!caustics_) return maps;
    for (std::size_t l = 0; l < caustics_->projection_maps.size(); ++l)
        if (!caustics_->projection_maps[l].empty())
            maps.push_back({caustics_->projection_maps[l], caustics_->light_positions[l], static_cast<int>(l)});
    return maps;
}

std::size_t RenderSession::fetch_tiles(Image& out, std::vector<std::uint64_t>& seen) const {
    if (out.width != image_.width || out.height != image_.height) {
        out = Image(image_.width, image_.height);
        seen.assign(tiles_.size(), 0);
    }
    seen.resize(tiles_.size(), 0);
    std::size_t copied = 0;
    for (std::size_t i = 0; i < tiles_.size(); ++i) {
        if (tile_versions_[i].load(std::memory_order_acquire) == seen[i]) continue;
        std::unique_lock lock(tile_mutexes_[i], std::try_to_lock);
        if (!lock.owns_lock()) continue;  // being rendered: next time
        const Tile& t = tiles_[i];
        for (int y = t.y0; y < t.y1; ++y)
            std::copy(&image_.at(t.x0, y), &image_.at(t.x0, y) + (t.x1 - t.x0), &out.at(t.x0, y));
        seen[i] = tile_versions_[i].load(std::memory_order_relaxed);
        ++copied;
    }
    return copied;
}

bool RenderSession::wait() {
    if (worker_.joinable()) worker_.join();
    if (error_) std::rethrow_exception(error_);
    std::lock_guard lock(mutex_);
    return progress_.finished;
}

bool RenderSession::wait_for_end(double seconds) const {
    std::unique_lock lock(mutex_);
    return ended_.wait_for(lock, std::chrono::duration<double>(std::max(0.0, seconds)),
                           [&] { return !progress_.running; });
}

SessionProgress RenderSession::progress() const {
    std::lock_guard lock(mutex_);
    SessionProgress p = progress_;
    p.tiles_done = tiles_done_.load(std::memory_order_relaxed);
    p.photons_done = photon_progress_.load(std::memory_order_relaxed);
    if (p.running) p.elapsed_seconds = now_seconds() - start_time_;
    return p;
}

RenderStats RenderSession::stats() const {
    std::lock_guard lock(mutex_);
    return stats_;
}

std::vector<std::string> RenderSession::warnings() const {
    std::lock_guard lock(mutex_);
    return warnings_;
}

RenderSession::StageCounters RenderSession::stage_counters() const {
    std::lock_guard lock(mutex_);
    return counters_;
}

}  // namespace caustica
