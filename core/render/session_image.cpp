// RenderSession's image passes: the shading setup of its job, the direct-light preview shown while
// photons are shot, and the passes that make the image (an integrator's own render loop through
// RenderHost, the classic tile passes with their layers and render region, or the ranks' tiles).
// Each pass runs on the session's tiles through PassRunner (core/render/session_passes.h).
#include "core/render/render_session.h"

#include "core/render/session_passes.h"

#include "core/geometry/render_scene.h"
#include "core/integrators/registry.h"
#include "core/photons/caustic_stage.h"
#include "core/render/render_layers.h"
#include "core/render/tile_renderer.h"
#include "core/scene/camera.h"

#include <tbb/task_arena.h>

#include <memory>
#include <random>

namespace caustica {

ShadingSetup RenderSession::make_setup() const {
    const Options& options = job_.options;
    const int width = job_.width, height = job_.height;
    ShadingSetup setup;
    setup.scene = scene_.get();
    setup.cancel = &cancel_requested_;
    setup.lights = job_lights(job_);
    setup.ambient = glm::vec3(job_.ambient);
    setup.miss_colour = glm::vec3(job_.miss_colour);
    setup.sky = options.rays;
    // The --rays sunburst's frame, right = view x up (up as written, normalised).
    const glm::dvec3 view = glm::normalize(job_.camera.view), up = glm::normalize(job_.camera.up);
    const glm::dvec3 right = glm::cross(view, up);
    if (glm::length(right) > 0.0) setup.view_right = glm::vec3(glm::normalize(right));
    setup.view_up = glm::vec3(up);
    setup.shadow_grid = options.shadow_grid;
    setup.soft_shadows = !options.no_soft_shadows;
    // The smallest unit distances are below float's normal range: keep the divisor positive.
    setup.unit_distance = std::max(static_cast<float>(options.unit_distance), std::numeric_limits<float>::min());
    setup.textures = textures_.get();
    setup.draw_caustics_only = options.draw_caustics_only;
    setup.draw_caustic_map = options.draw_caustic_map;
    setup.draw_gi_only = options.draw_gi_only;
    setup.layer = options.show_layer;
    setup.draw_gi_map = options.draw_gi_map;
    setup.dot_radius_per_distance =
        static_cast<float>(std::tan(glm::radians(vertical_fov_degrees(job_.camera, width, height)) * 0.5) * 2.0 / height);
    return setup;
}

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
        return session_.coarse_preview_ && !session_.direct_first_ ? session_.preview_block_ : 0;
    }
    bool direct_preview_shown() const override { return session_.direct_first_; }
    bool renders_layers() const override { return !session_.coarse_preview_; }
    Image& image() override { return session_.image_; }
    const std::vector<Tile>& tiles() const override { return session_.tiles_; }
    RenderRegion region() const override { return session_.region_in_image(); }
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

TileContext make_context(const Options& options, const Camera& camera, const Integrator& integrator,
                         const std::atomic<bool>& cancel) {
    TileContext context;
    context.integrator = &integrator;
    context.camera = &camera;
    context.cancel = &cancel;
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
    const std::unique_ptr<Integrator> integrator = make_integrator(job_.options.integrator, setup, job_.options);
    const TileContext context = make_context(job_.options, camera, *integrator, cancel_requested_);
    {
        std::lock_guard lock(mutex_);
        progress_.passes = 1;
        progress_.tiles_total = tiles_.size();
    }
    const RenderRegion region = region_in_image();
    PassRunner runner{*this, arena, {}};
    runner.run("preview", 0, [&](std::size_t, const Tile& tile, RayCounters& c) {
        if (const Tile part = region_part(tile, region); !tile_empty(part))
            render_coarse_tile(context, part, preview_block_, image_, c);
    });
    std::lock_guard lock(mutex_);
    progress_.showing_direct_light = !cancel_requested_;
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
    const std::unique_ptr<Integrator> integrator = make_integrator(options.integrator, setup, options);
    TileContext context = make_context(options, camera, *integrator, cancel_requested_);
    PassRunner runner{*this, arena, {}};
    layers_.clear();

    if (options.accumulates() && loop_) {
        Host host(*this, runner);
        loop_->run(host, setup, context);
        if (options.layers && !cancel_requested_) layers_ = loop_->layer_images();
    } else if (distributed()) {
        // --layers: every rank renders its tiles' layers too, and rank 0 collects them with the tiles.
        LayerRender layers(setup, options, width, height, !coarse_preview_);
        context.layers = layers.targets();
        render_distributed_classic(runner, context);
        if (!cancel_requested_ && cluster_->rank() == 0) layers_ = layers.take_images();
    } else {
        const std::vector<Tile>& tiles = tiles_;
        // With a region, only its pixels are rendered again; the others keep the last image.
        const RenderRegion region = region_in_image();
        refine_.assign(static_cast<std::size_t>(width) * height, 0);
        context.refine = &refine_;
        // Nothing unless --layers, and nothing in the preview (coarse passes), which shows no layers.
        LayerRender layers(setup, options, width, height, !coarse_preview_);
        context.layers = layers.targets();
        const bool antialias = has_antialiasing_pass(context);
        {
            std::lock_guard lock(mutex_);
            progress_.passes = (antialias ? 2 : 1) + (coarse_preview_ ? 1 : 0);
            progress_.tiles_total = tiles.size() * progress_.passes;
        }
        // The coarse pass is pass 0; a direct-light preview shown before the photons took its place.
        int pass = coarse_preview_ ? 1 : 0;
        if (coarse_preview_ && !direct_first_)
            runner.run("preview", 0, [&](std::size_t, const Tile& tile, RayCounters& c) {
                if (const Tile part = region_part(tile, region); !tile_empty(part))
                    render_coarse_tile(context, part, preview_block_, image_, c);
            });
        if (!cancel_requested_)
            runner.run("first samples", pass++, [&](std::size_t, const Tile& tile, RayCounters& c) {
                if (const Tile part = region_part(tile, region); !tile_empty(part))
                    render_first_pass_tile(context, part, image_, c);
            });
        if (antialias && !cancel_requested_) {
            first_pass_ = image_;
            runner.run("anti-aliasing", pass++, [&](std::size_t, const Tile& tile, RayCounters& c) {
                if (const Tile part = region_part(tile, region); !tile_empty(part))
                    render_antialiasing_tile(context, part, first_pass_, image_, c);
            });
        }
        if (!cancel_requested_) layers_ = layers.take_images();
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

}  // namespace caustica
