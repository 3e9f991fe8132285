#include "core/render/render_session.h"

#include "core/scene/camera.h"
#include "core/photons/caustic_stage.h"
#include "core/util/denormals.h"
#include "core/integrators/registry.h"
#include "core/render/random.h"
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
namespace {

double now_seconds() {
    using clock = std::chrono::steady_clock;
    return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

std::uint64_t hash_vec(std::uint64_t h, const glm::dvec3& v) {
    return hash_double(hash_double(hash_double(h, v.x), v.y), v.z);
}

/// Folds an index that may be -1 (none) into a running hash, in unsigned arithmetic.
std::uint64_t hash_index(std::uint64_t h, int index) {
    return hash_combine(h, static_cast<std::uint64_t>(static_cast<std::int64_t>(index) + 1));
}

}  // namespace

namespace {

/// What the BVH and materials depend on; meshes by address (a cache key within this process) or,
/// `by_content`, by their vertices (the same in every process that loaded the same files).
std::uint64_t hash_geometry(const RenderJob& job, bool by_content) {
    std::uint64_t h = hash_combine(0x6361757374696361ULL, static_cast<std::uint64_t>(job.root));
    h = hash_options_feeding(h, job.options, stage_scene);
    const SceneDesc& scene = *job.scene;
    for (const NodeDesc& node : scene.nodes) {
        h = hash_combine(h, static_cast<std::uint64_t>(node.kind));
        for (const TransformOp& op : node.transforms) {
            h = hash_combine(h, static_cast<std::uint64_t>(op.kind) * 4 + static_cast<std::uint64_t>(op.axis));
            h = hash_double(hash_vec(h, op.amount), op.degrees);
        }
        for (int child : node.children) h = hash_index(h, child);
        h = hash_index(h, node.material);
        h = hash_double(hash_vec(h, node.position), node.size);
        h = hash_index(h, node.mesh);
        h = hash_index(hash_index(h, node.csg_left), node.csg_right);
    }
    for (const MaterialDesc& m : scene.materials) {
        h = hash_double(hash_vec(hash_vec(h, m.kd), m.ks), m.shininess);
        h = hash_combine(h, (m.reflective ? 1 : 0) + (m.air ? 2 : 0) + (m.refractive_index ? 4 : 0));
        h = hash_double(h, m.refractive_index.value_or(0.0));
        h = hash_index(hash_index(h, m.texture), m.bumpmap);
    }
    for (const TextureDesc& t : scene.textures) {
        h = hash_combine(h, std::hash<std::string>{}(t.source));
        h = hash_combine(h, std::hash<std::string>{}(t.remap) + (t.procedural ? 1 : 0));
    }
    for (const auto& mesh : scene.meshes) {
        if (!by_content || !mesh) {
            h = hash_combine(h, reinterpret_cast<std::uintptr_t>(mesh.get()));
            continue;
        }
        h = hash_combine(h, mesh->positions.size() * 31 + mesh->triangles.size());
        for (const glm::vec3& p : mesh->positions) h = hash_double(hash_double(hash_double(h, p.x), p.y), p.z);
        for (const glm::uvec3& t : mesh->triangles)
            h = hash_combine(h, (std::uint64_t(t.x) << 42) ^ (std::uint64_t(t.y) << 21) ^ t.z);
        for (const glm::vec2& uv : mesh->texcoords) h = hash_double(hash_double(h, uv.x), uv.y);
    }
    return h;
}

}  // namespace

std::uint64_t geometry_fingerprint(const RenderJob& job) { return hash_geometry(job, false); }

std::uint64_t job_content_fingerprint(const RenderJob& job) {
    std::uint64_t h = hash_geometry(job, true);
    h = hash_options_feeding(h, job.options, stage_scene | stage_photons | stage_image | stage_output);
    h = hash_vec(hash_vec(hash_vec(h, job.camera.eye), job.camera.view), job.camera.up);
    h = hash_double(h, job.camera.fovy_degrees);
    h = hash_combine(hash_combine(h, static_cast<std::uint64_t>(job.width)), static_cast<std::uint64_t>(job.height));
    h = hash_vec(hash_vec(h, job.ambient), job.miss_colour);
    for (int l : job.lights) {
        const LightDesc& light = job.scene->lights.at(static_cast<std::size_t>(l));
        h = hash_double(hash_vec(hash_vec(hash_vec(h, light.position), light.colour), light.falloff), light.radius);
    }
    return h;
}

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

void RenderSession::set_stop_rules(int passes, double time_limit, double target_error) {
    cancel();
    if (worker_.joinable()) worker_.join();
    job_.options.passes = passes;
    job_.options.passes_given = true;
    job_.options.time_limit = time_limit;
    job_.options.target_error = target_error;
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
    if (caustics_ && caustics_->key == caustic_key_) {
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
    inputs.cluster = cluster_ && cluster_->size() > 1 ? cluster_ : nullptr;
    inputs.progress = &photon_progress_;
    integrator.build_photons(*fresh, *scene_, job_, inputs);
    fresh->key = cancel_requested_ ? 0 : caustic_key_;  // a cancelled pass is not reused
    std::lock_guard lock(mutex_);  // published at once: the preview shows maps and counts early
    caustics_ = std::move(fresh);
    ++counters_.photon_passes;
    stats_.stages.push_back({"projection maps", caustics_->map_seconds, false});
    stats_.stages.push_back({"photon shooting", caustics_->shoot_seconds, false});
    stats_.stages.push_back({"photon k-d tree", caustics_->tree_seconds, false});
    for (const std::string& w : caustics_->warnings) warnings_.push_back(w);
    publish_caustic_stats();
}

void RenderSession::publish_caustic_stats() {
    stats_.caustic_lights = caustics_->lights;
    stats_.caustic_photons = caustics_->map ? caustics_->map->size() : 0;
    stats_.caustic_map_bytes = caustics_->map ? caustics_->map->memory_bytes() : 0;
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
    if (image_.width != job_.width || image_.height != job_.height) {
        image_ = Image(job_.width, job_.height);
        tiles_ = make_tiles(job_.width, job_.height, tile_size);
        tile_mutexes_ = std::make_unique<std::mutex[]>(tiles_.size());
        tile_versions_ = std::make_unique<std::atomic<std::uint64_t>[]>(tiles_.size());
        for (std::size_t i = 0; i < tiles_.size(); ++i) tile_versions_[i] = 0;
    }
    start_time_ = now_seconds();
    running_ = true;
    worker_ = std::thread([this] { run(); });
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
            // An accumulating preview shows direct light at once: a coarse pass before photons
            // that are not cached yet are shot.
            direct_first_ = progressive_ && job_.options.accumulates() && !(loop_ && loop_->resumable()) && caustic_key_ != 0 &&
                            !(caustics_ && caustics_->key == caustic_key_);
            if (direct_first_) render_direct_preview(arena);
            if (cancel_requested_) return;
            prepare_caustics();
            if (cancel_requested_) return;
            {
                std::lock_guard lock(mutex_);
                progress_.prepared = true;
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
    std::lock_guard lock(mutex_);
    progress_.running = false;
    progress_.cancelled = cancel_requested_.load();
    progress_.finished = !error_ && !progress_.cancelled;
    progress_.elapsed_seconds = now_seconds() - start_time_;
    stats_.total_seconds = progress_.elapsed_seconds;
    running_ = false;
}

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

ShadingSetup RenderSession::make_setup() const {
    const Options& options = job_.options;
    const int width = job_.width, height = job_.height;
    ShadingSetup setup;
    setup.scene = scene_.get();
    setup.lights = job_lights(job_);
    setup.ambient = glm::vec3(job_.ambient);
    setup.miss_colour = glm::vec3(job_.miss_colour);
    setup.sky = options.rays;
    // The --rays sunburst's frame, right = view x up (up as written, normalised).
    const glm::dvec3 view = glm::normalize(job_.camera.view), up = glm::normalize(job_.camera.up);
    const glm::dvec3 right = glm::cross(view, up);
    if (glm::length(right) > 0.0) setup.view_right = glm::vec3(glm::normalize(right));
    setup.view_up = glm::vec3(up);
    setup.max_depth = options.max_depth;
    setup.min_weight = static_cast<float>(options.min_weight);
    setup.shadow_grid = options.shadow_grid;
    setup.soft_shadows = !options.no_soft_shadows;
    // The smallest unit distances are below float's normal range: keep the divisor positive.
    setup.unit_distance = std::max(static_cast<float>(options.unit_distance), std::numeric_limits<float>::min());
    setup.textures = textures_.get();
    setup.caustic_neighbours = options.caustic_num_neighbours;
    setup.caustic_max_distance = static_cast<float>(options.effective_caustic_max_dist());
    setup.caustic_filter = options.caustic_cone_filter ? PhotonFilter::cone : PhotonFilter::none;
    setup.gi_neighbours = options.gi_num_neighbours;
    setup.draw_caustics_only = options.draw_caustics_only;
    setup.draw_caustic_map = options.draw_caustic_map;
    setup.draw_gi_only = options.draw_gi_only;
    setup.draw_gi_map = options.draw_gi_map;
    setup.dot_radius_per_distance =
        static_cast<float>(std::tan(glm::radians(vertical_fov_degrees(job_.camera, width, height)) * 0.5) * 2.0 / height);
    return setup;
}

/// Runs one image pass over every tile on the arena: each tile under its lock, then published
/// with a new version, so a viewer copying tiles (fetch_tiles) never sees one half-written and
/// never waits (it try-locks).
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
                    session.tile_versions_[t].store(++session.version_counter_, std::memory_order_release);
                }
            });
        });
    }

    RayCounters total() const {
        RayCounters t;
        for (const RayCounters& c : counters) t += c;
        return t;
    }
};

/// The session as a render loop sees it (RenderHost): its job and stages, its tiles run by a
/// PassRunner, its progress under the mutex.
class RenderSession::Host final : public RenderHost {
public:
    Host(RenderSession& session, PassRunner& runner) : session_(session), runner_(runner) {}

    const RenderJob& job() const override { return session_.job_; }
    const RenderScene& scene() const override { return *session_.scene_; }
    const CausticStage* photon_stage() const override {
        return session_.caustic_key_ != 0 ? session_.caustics_.get() : nullptr;
    }
    const std::atomic<bool>& cancel_flag() const override { return session_.cancel_requested_; }
    Cluster* cluster() const override { return session_.distributed() ? session_.cluster_ : nullptr; }
    double elapsed_seconds() const override { return now_seconds() - session_.start_time_; }
    int coarse_preview_block() const override {
        return session_.progressive_ && !session_.direct_first_ ? session_.preview_block_ : 0;
    }
    bool direct_preview_shown() const override { return session_.direct_first_; }
    Image& image() override { return session_.image_; }
    const std::vector<Tile>& tiles() const override { return session_.tiles_; }
    void run_tiles(const char* stage, int pass, const TileBody& body) override { runner_.run(stage, pass, body); }
    void publish_tiles(const std::function<void(const Tile&)>& fill) override {
        for (std::size_t i = 0; i < session_.tiles_.size(); ++i) {
            std::lock_guard tile_lock(session_.tile_mutexes_[i]);
            fill(session_.tiles_[i]);
            session_.tile_versions_[i].store(++session_.version_counter_, std::memory_order_release);
        }
    }
    RayCounters ray_totals() const override { return runner_.total(); }
    void report(const std::function<void(SessionProgress&, RenderStats&)>& update) override {
        std::lock_guard lock(session_.mutex_);
        update(session_.progress_, session_.stats_);
    }
    void add_stage_time(const char* stage, double seconds) override {
        std::lock_guard lock(session_.mutex_);
        session_.add_stage_time(stage, seconds);
    }
    void set_stage(const char* stage) override { session_.set_stage(stage); }
    std::atomic<long long>& photon_progress() override { return session_.photon_progress_; }

private:
    RenderSession& session_;
    PassRunner& runner_;
};

namespace {

TileContext make_context(const Options& options, const Camera& camera, const Integrator& integrator) {
    TileContext context;
    context.integrator = &integrator;
    context.camera = &camera;
    context.seed = options.reproducible ? static_cast<std::uint64_t>(options.seed)
                                        : (static_cast<std::uint64_t>(options.seed) ^ std::random_device{}());
    context.aa_grid = options.disable_aa ? 1 : options.aa_grid;
    context.aa_threshold = static_cast<float>(options.aa_threshold);
    context.draw_aa = options.draw_aa;
    return context;
}

}  // namespace

void RenderSession::render_direct_preview(tbb::task_arena& arena) {
    const Camera camera(job_.camera, job_.width, job_.height);
    const ShadingSetup setup = make_setup();  // no photon map yet: direct light only
    const std::unique_ptr<Integrator> integrator = make_integrator(job_.options.integrator, setup);
    const TileContext context = make_context(job_.options, camera, *integrator);
    {
        std::lock_guard lock(mutex_);
        progress_.passes = 1;
        progress_.tiles_total = tiles_.size();
    }
    PassRunner runner{*this, arena, {}};
    runner.run("preview", 0, [&](std::size_t, const Tile& tile, RayCounters& c) {
        render_coarse_tile(context, tile, preview_block_, image_, c);
    });
}

void RenderSession::render_passes(tbb::task_arena& arena, int threads) {
    const Options& options = job_.options;
    const int width = job_.width, height = job_.height;
    const Camera camera(job_.camera, width, height);
    ShadingSetup setup = make_setup();
    if (caustics_ && caustics_->map) setup.caustic_map = caustics_->map.get();
    if (caustics_ && caustics_->gi_map) setup.gi_map = caustics_->gi_map.get();
    if (options.show_projection_map && caustics_)
        for (std::size_t l = 0; l < caustics_->projection_maps.size(); ++l)
            if (!caustics_->projection_maps[l].empty())
                setup.projection_maps.emplace_back(&caustics_->projection_maps[l], caustics_->light_positions[l]);
    const std::unique_ptr<Integrator> integrator = make_integrator(options.integrator, setup);
    TileContext context = make_context(options, camera, *integrator);
    PassRunner runner{*this, arena, {}};

    if (options.accumulates() && loop_) {
        Host host(*this, runner);
        loop_->run(host, setup, context);
    } else if (distributed()) {
        render_distributed_classic(runner, context);
    } else {
        const std::vector<Tile>& tiles = tiles_;
        refine_.assign(static_cast<std::size_t>(width) * height, 0);
        context.refine = &refine_;
        const bool antialias = has_antialiasing_pass(context);
        {
            std::lock_guard lock(mutex_);
            progress_.passes = (antialias ? 2 : 1) + (progressive_ ? 1 : 0);
            progress_.tiles_total = tiles.size() * progress_.passes;
        }
        int pass = 0;
        if (progressive_)
            runner.run("preview", pass++, [&](std::size_t, const Tile& tile, RayCounters& c) {
                render_coarse_tile(context, tile, preview_block_, image_, c);
            });
        if (!cancel_requested_)
            runner.run("first samples", pass++, [&](std::size_t, const Tile& tile, RayCounters& c) {
                render_first_pass_tile(context, tile, image_, c);
            });
        if (antialias && !cancel_requested_) {
            first_pass_ = image_;
            runner.run("anti-aliasing", pass++, [&](std::size_t, const Tile& tile, RayCounters& c) {
                render_antialiasing_tile(context, tile, first_pass_, image_, c);
            });
        }
    }
    RayCounters rays = runner.total();
    if (distributed()) {  // what every rank traced
        cluster_->checkpoint(nullptr, &cancel_requested_);
        for (std::uint64_t* count : {&rays.samples, &rays.supersampled_pixels, &rays.primary, &rays.shadow,
                                     &rays.reflected, &rays.refracted, &rays.gathers})
            *count = static_cast<std::uint64_t>(cluster_->all_sum(static_cast<long long>(*count)));
    }
    std::lock_guard lock(mutex_);
    stats_.rays = rays;
    stats_.threads = threads;
    stats_.integrator = integrator->name();
    ++counters_.renders;
}

// A tile's result: its pixels, row by row, then (classic) its pixels' corner_grid refine flags.
Cluster::Bytes RenderSession::tile_bytes(int first, int last) const {
    Cluster::Bytes bytes;
    for (int i = first; i < last; ++i) {
        const Tile& t = tiles_[static_cast<std::size_t>(i)];
        const std::size_t width = static_cast<std::size_t>(t.x1 - t.x0);
        for (int y = t.y0; y < t.y1; ++y) {
            const auto* row = reinterpret_cast<const std::uint8_t*>(&image_.at(t.x0, y));
            bytes.insert(bytes.end(), row, row + sizeof(glm::vec3) * width);
            const std::uint8_t* flags = refine_.data() + static_cast<std::size_t>(y) * image_.width + t.x0;
            bytes.insert(bytes.end(), flags, flags + width);
        }
    }
    return bytes;
}

void RenderSession::put_tile_bytes(int first, int last, const Cluster::Bytes& bytes) {
    std::size_t at = 0;
    for (int i = first; i < last; ++i) {
        const std::size_t index = static_cast<std::size_t>(i);
        const Tile& t = tiles_[index];
        const std::size_t width = static_cast<std::size_t>(t.x1 - t.x0), row_bytes = (sizeof(glm::vec3) + 1) * width;
        if (at + row_bytes * static_cast<std::size_t>(t.y1 - t.y0) > bytes.size())
            throw std::runtime_error("tile results from another rank are truncated");
        std::lock_guard tile_lock(tile_mutexes_[index]);
        for (int y = t.y0; y < t.y1; ++y, at += row_bytes) {
            std::memcpy(&image_.at(t.x0, y), bytes.data() + at, sizeof(glm::vec3) * width);
            std::memcpy(refine_.data() + static_cast<std::size_t>(y) * image_.width + t.x0,
                        bytes.data() + at + sizeof(glm::vec3) * width, width);
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
            return tile_bytes(first, last);
        };
        const Cluster::CollectFn collect = [&](int first, int last, const Cluster::Bytes& bytes) {
            put_tile_bytes(first, last, bytes);
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
    const std::size_t pixels = static_cast<std::size_t>(width) * height;
    Cluster::Bytes first;
    std::exception_ptr error;
    try {
        first.reserve(pixels * sizeof(glm::vec3) + pixels);
        if (cluster_->rank() == 0) {
            first.resize(pixels * sizeof(glm::vec3) + pixels);
            std::memcpy(first.data(), image_.pixels.data(), pixels * sizeof(glm::vec3));
            std::memcpy(first.data() + pixels * sizeof(glm::vec3), refine_.data(), pixels);
        }
    } catch (...) {
        error = std::current_exception();
    }
    cluster_->checkpoint(error, &cancel_requested_);
    cluster_->broadcast(first, 0);
    if (first.size() != pixels * sizeof(glm::vec3) + pixels)
        throw std::runtime_error("the first pass from rank 0 has the wrong size");
    if (cluster_->rank() != 0) {
        std::memcpy(image_.pixels.data(), first.data(), pixels * sizeof(glm::vec3));
        std::memcpy(refine_.data(), first.data() + pixels * sizeof(glm::vec3), pixels);
    }
    first_pass_ = image_;
    share("anti-aliasing", 1, [&](std::size_t, const Tile& tile, RayCounters& c) {
        render_antialiasing_tile(context, tile, first_pass_, image_, c);
    });
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

/// For inspect(): which node made each primitive, with world bounds to tell primitives of the same
/// material apart, and the materials' script lines.
struct RenderSession::InspectIndex {
    struct Primitive {
        int material = -1;  // RenderScene material index (the default material last)
        int node = -1;
        bool is_mesh = false;
        Shape shape;
        glm::mat4 world_to_object{1.0f};
        glm::vec3 lo{0.0f}, hi{0.0f};  // world bounds
    };
    struct CsgObject {
        int node = -1;
        glm::vec3 lo{0.0f}, hi{0.0f};
    };
    std::vector<Primitive> primitives;
    std::vector<CsgObject> csg;
    std::vector<std::string> node_names, node_wheres, material_wheres;
    std::vector<Material> materials;  // as RenderScene::materials()
};

namespace {

// World bounds of a placed primitive (mesh bounds are computed once per mesh).
void placed_bounds(const SceneDesc& desc, const PlacedPrimitive& p, std::vector<std::pair<glm::vec3, glm::vec3>>& mesh_boxes,
                   glm::vec3& lo, glm::vec3& hi) {
    glm::vec3 olo(0.0f), ohi(0.0f);
    if (p.is_mesh && p.mesh >= 0 && p.mesh < static_cast<int>(desc.meshes.size()) && desc.meshes[p.mesh]) {
        auto& box = mesh_boxes[static_cast<std::size_t>(p.mesh)];
        if (box.first.x > box.second.x) {
            for (const glm::vec3& v : desc.meshes[p.mesh]->positions) {
                box.first = glm::min(box.first, v);
                box.second = glm::max(box.second, v);
            }
        }
        olo = box.first;
        ohi = box.second;
    } else if (!p.is_mesh) {
        shape_bounds(p.shape, olo, ohi);
    }
    lo = glm::vec3(std::numeric_limits<float>::max());
    hi = -lo;
    const glm::mat4 m(p.object_to_world);
    for (int c = 0; c < 8; ++c) {
        const glm::vec3 corner((c & 1) ? ohi.x : olo.x, (c & 2) ? ohi.y : olo.y, (c & 4) ? ohi.z : olo.z);
        const glm::vec3 w(m * glm::vec4(corner, 1.0f));
        lo = glm::min(lo, w);
        hi = glm::max(hi, w);
    }
}

bool inside(const glm::vec3& p, const glm::vec3& lo, const glm::vec3& hi, float slack) {
    return glm::all(glm::greaterThanEqual(p, lo - slack)) && glm::all(glm::lessThanEqual(p, hi + slack));
}

}  // namespace

std::shared_ptr<const RenderSession::InspectIndex> RenderSession::make_inspect_index(const RenderJob& job) {
    FlatScene flat;
    try {
        flat = flatten_scene(job);  // validated when the scene was built: this does not throw
    } catch (const std::exception&) {
        return nullptr;
    }
    const SceneDesc& desc = *job.scene;
    auto index = std::make_shared<InspectIndex>();
    const float inf = std::numeric_limits<float>::max();
    std::vector<std::pair<glm::vec3, glm::vec3>> mesh_boxes(desc.meshes.size(), {glm::vec3(inf), glm::vec3(-inf)});
    const int default_material = static_cast<int>(desc.materials.size());
    for (const PlacedPrimitive& p : flat.primitives) {
        InspectIndex::Primitive q;
        q.material = p.material >= 0 ? p.material : default_material;
        q.node = p.node;
        q.is_mesh = p.is_mesh;
        q.shape = p.shape;
        q.world_to_object = glm::mat4(glm::inverse(p.object_to_world));
        placed_bounds(desc, p, mesh_boxes, q.lo, q.hi);
        index->primitives.push_back(q);
    }
    for (const FlatCsgObject& object : flat.csg_objects) {
        InspectIndex::CsgObject c{object.node, glm::vec3(inf), glm::vec3(-inf)};
        for (const PlacedPrimitive& leaf : object.leaves) {
            glm::vec3 lo, hi;
            placed_bounds(desc, leaf, mesh_boxes, lo, hi);
            c.lo = glm::min(c.lo, lo);
            c.hi = glm::max(c.hi, hi);
        }
        index->csg.push_back(c);
    }
    for (const NodeDesc& n : desc.nodes) {
        index->node_names.push_back(n.name);
        index->node_wheres.push_back(n.where.str());
    }
    for (const MaterialDesc& m : desc.materials) {
        index->material_wheres.push_back(m.where.str());
        index->materials.push_back(Material::from_desc(m));
    }
    return index;
}

std::optional<SurfaceInspection> RenderSession::inspect(const Ray& ray, const Options& options) const {
    std::shared_ptr<const RenderScene> scene;
    std::shared_ptr<const RenderJob> job;
    {
        std::lock_guard lock(mutex_);
        scene = scene_;
        job = inspect_job_;
    }
    SurfaceHit hit;
    if (!scene || !scene->intersect(ray, hit)) return std::nullopt;
    // The node index is built on the first inspection of a scene (flattening it again), so that
    // renders that never inspect pay nothing for it.
    std::shared_ptr<const InspectIndex> index;
    {
        std::lock_guard lock(inspect_mutex_);
        if (index_job_ != job) {
            inspect_index_ = job && job->scene ? make_inspect_index(*job) : nullptr;
            index_job_ = job;
        }
        index = inspect_index_;
    }
    SurfaceInspection out;
    out.point = hit.position;
    out.distance = hit.t;
    const std::vector<Material>& materials = scene->materials();
    if (hit.material >= 0 && hit.material < static_cast<int>(materials.size())) {
        const Material& m = materials[static_cast<std::size_t>(hit.material)];
        out.kd = m.kd;
        out.ks = m.ks;
        out.reflective = m.reflective;
        out.transparent = m.transparent;
    }
    if (index) {
        const bool scripted = hit.material >= 0 && hit.material < static_cast<int>(index->material_wheres.size());
        out.material = scripted ? hit.material : -1;
        if (scripted) out.material_where = index->material_wheres[static_cast<std::size_t>(hit.material)];
        // The node: among the primitives of the hit's material, an analytic shape the ray crosses
        // at the hit's distance, else a mesh or CSG object whose bounds hold the point.
        const float slack = 1e-3f * (1.0f + glm::length(hit.position));
        int node = -1;
        float best = std::numeric_limits<float>::max();
        if (hit.in_csg) {
            for (const InspectIndex::CsgObject& c : index->csg)
                if (inside(hit.position, c.lo, c.hi, slack)) {
                    node = c.node;
                    break;
                }
        } else {
            for (const InspectIndex::Primitive& p : index->primitives) {
                if (p.material != hit.material || !inside(hit.position, p.lo, p.hi, slack)) continue;
                float miss = 1e30f;  // a mesh whose bounds hold the point: any analytic crossing wins
                if (!p.is_mesh) {
                    const glm::vec3 o(p.world_to_object * glm::vec4(ray.origin, 1.0f));
                    const glm::vec3 d(p.world_to_object * glm::vec4(ray.direction, 0.0f));
                    ShapeInterval interval;
                    if (!intersect_shape_interval(p.shape, o, d, interval)) continue;
                    miss = std::min(std::abs(interval.entry.t - hit.t), std::abs(interval.exit.t - hit.t));
                    if (miss > slack * (1.0f + hit.t)) continue;
                }
                if (miss < best) {
                    best = miss;
                    node = p.node;
                }
            }
        }
        if (node >= 0 && node < static_cast<int>(index->node_names.size())) {
            out.object = index->node_names[static_cast<std::size_t>(node)];
            out.object_where = index->node_wheres[static_cast<std::size_t>(node)];
        }
    }
    // The caustic gather as the integrator does it, at the shading normal facing the ray.
    const glm::vec3 n = glm::dot(hit.normal, ray.direction) > 0.0f ? -hit.normal : hit.normal;
    std::shared_ptr<const CausticStage> stage;
    {
        std::lock_guard lock(mutex_);  // caustics_ is replaced under it; the query runs outside
        stage = caustics_;
    }
    if (!stage || !stage->map || stage->map->size() == 0) return out;
    // N is validated: at most a million.
    std::vector<Neighbour> scratch(static_cast<std::size_t>(std::max(options.caustic_num_neighbours, 1)));
    out.map_photons = stage->map->size();
    out.caustic =
        integrator_entry(options.integrator).caustic_readout(*stage->map, hit.position, n, out.kd, options, scratch.data());
    return out;
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
