#include "ui/view_model.h"

#include "core/scene/camera.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace caustica::ui {
namespace {

bool same_camera(const CameraDesc& a, const CameraDesc& b) {
    return a.eye == b.eye && a.view == b.view && a.up == b.up && a.fovy_degrees == b.fovy_degrees;
}

bool same_file(const std::string& a, const std::string& b) {
    if (a.empty() || b.empty()) return false;
    std::error_code ec;
    const bool same = std::filesystem::equivalent(a, b, ec);
    return ec ? a == b : same;
}

LoadSettings load_settings(const ModelConfig& config) {
    LoadSettings settings;
    settings.timeout_seconds = config.script_timeout;
    settings.memory_limit_bytes = config.script_memory_bytes;
    settings.allow_read = config.allow_read;
    settings.output_given = true;  // the preview saves where the user says, never to the script's names
    apply_option_tokens(settings.base_options, config.default_tokens);
    return settings;
}

/// Whether option tokens set a progressive stopping rule (any value, --passes 1 too).
bool sets_stop_rules(const std::vector<std::string>& tokens) {
    Options probe;
    probe.passes = -1;  // values no token can give
    probe.time_limit = probe.target_error = -1.0;
    apply_option_tokens(probe, tokens);
    return probe.passes != -1 || probe.time_limit != -1.0 || probe.target_error != -1.0;
}

}  // namespace

ViewModel::ViewModel(ModelConfig config)
    : config_(std::move(config)), source_(load_settings(config_), config_.recent_file), driver_(config_.driver) {
    try {
        command_line_stop_rules_ = sets_stop_rules(config_.option_tokens);
    } catch (const std::exception&) {
        // bad tokens are reported by the first compose()
    }
}

ViewModel::~ViewModel() {
    if (overlay_trace_.valid()) overlay_trace_.wait();
}

// --- scenes

void ViewModel::open(const std::string& path) {
    watched_path_ = path;
    source_.open(path);
}

void ViewModel::reload() {
    if (!watched_path_.empty()) source_.open(watched_path_);
}

void ViewModel::select_render(int index) {
    if (!scene_ || index < 0 || index >= render_count() || index == inputs_.render_index) return;
    inputs_.render_index = index;
    const CameraDesc& camera = scene_->renders[index].camera;
    orbit_ = OrbitCamera(camera, default_target_distance(camera));
    target_known_ = false;
    mark_dirty();
}

std::vector<std::string> ViewModel::warnings() const {
    std::vector<std::string> all = scene_ ? scene_->warnings : std::vector<std::string>{};
    for (const std::string& w : driver_.session().warnings()) all.push_back(w);
    return all;
}

void ViewModel::install(LoadedScene loaded) {
    const bool reloaded = same_file(loaded.path, scene_path_);
    if (!loaded.error.empty()) {  // the shown scene stays; the failed file is watched for a fix
        error_ = loaded.error;
        watch_current();
        return;
    }
    error_.clear();
    scene_ = std::make_shared<const SceneScript>(std::move(loaded.script));
    scene_path_ = loaded.path;
    inputs_.scene = scene_;
    inputs_.scene_path = scene_path_;
    if (!reloaded) {
        inputs_.render_index = 0;
        inputs_.overrides.clear();  // another scene has other scales: start from its own knobs
        source_.add_recent(scene_path_);
    }
    inputs_.render_index = std::clamp(inputs_.render_index, 0, render_count() - 1);
    if (!reloaded || !orbit_.moved()) {
        const CameraDesc& camera = scene_->renders[inputs_.render_index].camera;
        orbit_ = OrbitCamera(camera, default_target_distance(camera));
        target_known_ = false;
    }
    watch_current();
    mark_dirty();
}

void ViewModel::watch_current() {
    std::vector<std::string> dependencies;
    if (scene_ && same_file(watched_path_, scene_path_))
        for (const RenderJob& job : scene_->renders) {
            for (const auto& mesh : job.scene->meshes)
                if (mesh && !mesh->path.empty()) dependencies.push_back(mesh->path);
            for (const TextureDesc& t : job.scene->textures)
                if (!t.procedural && !t.source.empty()) dependencies.push_back(t.source);
        }
    std::sort(dependencies.begin(), dependencies.end());
    dependencies.erase(std::unique(dependencies.begin(), dependencies.end()), dependencies.end());
    source_.watch(watched_path_, dependencies);
}

// --- camera

void ViewModel::orbit(double yaw_degrees, double pitch_degrees) {
    if (!scene_ || (yaw_degrees == 0.0 && pitch_degrees == 0.0)) return;
    orbit_.orbit(yaw_degrees, pitch_degrees);
    mark_dirty();
}

void ViewModel::zoom(double steps) {
    if (!scene_ || steps == 0.0) return;
    orbit_.zoom(std::pow(0.9, steps));
    mark_dirty();
}

void ViewModel::pan(glm::dvec2 image_pixels) {
    if (!scene_ || (image_pixels.x == 0.0 && image_pixels.y == 0.0)) return;
    const RenderJob& shown = driver_.has_job() ? driver_.job() : current_job();
    orbit_.pan_pixels(image_pixels, shown.width, shown.height);
    mark_dirty();
}

bool ViewModel::set_target_at(glm::vec2 image_pixel) {
    if (!scene_) return false;
    const RenderJob job = driver_.has_job() ? driver_.job() : current_job();
    const Camera camera(orbit_.desc(), job.width, job.height);
    glm::vec3 point;
    if (!driver_.session().pick(camera.generate(image_pixel.x, image_pixel.y), point)) return false;
    orbit_.set_target(glm::dvec3(point));
    target_known_ = true;
    mark_dirty();
    return true;
}

void ViewModel::reset_camera() {
    if (!scene_) return;
    const CameraDesc& camera = scene_->renders[inputs_.render_index].camera;
    orbit_ = OrbitCamera(camera, default_target_distance(camera));
    target_known_ = false;
    mark_dirty();
}

void ViewModel::resolve_target() {
    // The initial orbit target: the first surface along the script's view direction.
    if (target_known_ || !scene_) return;
    if (orbit_.moved()) {
        target_known_ = true;
        return;
    }
    if (!driver_.has_job() || driver_.job().scene != scene_->renders[inputs_.render_index].scene) return;
    const SessionProgress& p = driver_.progress();
    if (p.tiles_total == 0 && !p.finished) return;  // the scene is not built yet
    const RenderJob& job = driver_.job();
    const Camera camera(orbit_.desc(), job.width, job.height);
    glm::vec3 point;
    if (driver_.session().pick(camera.generate(0.5f * job.width, 0.5f * job.height), point))
        orbit_.set_target_distance(glm::length(glm::dvec3(point) - orbit_.eye()));
    target_known_ = true;
    if (pending_orbit_) {  // --orbit: around the same target an interactive drag would use
        orbit(pending_orbit_->x, pending_orbit_->y);
        pending_orbit_.reset();
    }
}

// --- knobs and settings

CausticKnobs ViewModel::script_knobs(const JobInputs& inputs) const {
    if (!inputs.scene) return {};
    Options options = inputs.scene->renders[inputs.render_index].options;
    apply_option_tokens(options, config_.option_tokens);
    return CausticKnobs::from(options);
}

CausticKnobs ViewModel::effective_knobs(const JobInputs& inputs) const {
    return inputs.overrides.merge(script_knobs(inputs), inputs.person_knobs);
}

CausticKnobs ViewModel::knobs() const { return effective_knobs(inputs_); }

bool ViewModel::same_inputs(const JobInputs& a, const JobInputs& b) const {
    return a.scene == b.scene && a.render_index == b.render_index && effective_knobs(a) == effective_knobs(b) &&
           a.threads == b.threads && a.resolution_scale == b.resolution_scale;
}

void ViewModel::set_knobs(const CausticKnobs& knobs) {
    const CausticKnobs current = this->knobs();
    if (knobs == current) return;
    inputs_.overrides.record(current, knobs);
    inputs_.person_knobs = knobs;
    mark_dirty();
}

void ViewModel::reset_knobs() {
    if (!inputs_.overrides.any()) return;
    inputs_.overrides.clear();
    mark_dirty();
}

void ViewModel::set_resolution_scale(double scale) {
    scale = std::clamp(scale, 0.1, 2.0);
    if (scale == inputs_.resolution_scale) return;
    inputs_.resolution_scale = scale;
    mark_dirty();
}

int ViewModel::threads() const { return scene_ ? current_job().options.threads : std::max(0, inputs_.threads); }

void ViewModel::set_threads(int threads) {
    threads = std::max(0, threads);
    if (threads == this->threads()) return;
    inputs_.threads = threads;
    mark_dirty();
}

// --- progressive refinement

StopRules ViewModel::stop_rules_for(const RenderJob& script_job, const Options& options) const {
    if (person_stop_rules_) return *person_stop_rules_;
    const bool given = command_line_stop_rules_ || script_job.option_origin("passes") ||
                       script_job.option_origin("time") || script_job.option_origin("target-error");
    return given ? StopRules::of(options) : StopRules{};  // none given: refine until paused
}

StopRules ViewModel::stop_rules() const {
    if (!scene_ || person_stop_rules_) return person_stop_rules_.value_or(StopRules{});
    const RenderJob& script_job = scene_->renders[inputs_.render_index];
    Options options = script_job.options;
    try {
        apply_option_tokens(options, config_.option_tokens);
    } catch (const std::exception&) {
        // compose() reports bad tokens
    }
    return stop_rules_for(script_job, options);
}

void ViewModel::set_stop_rules(const StopRules& rules) {
    if (rules == stop_rules()) return;
    person_stop_rules_ = rules;
    driver_.set_stop_rules(rules);  // the job to come carries them too (compose)
}

void ViewModel::set_paused(bool paused) {
    if (paused) driver_.pause();
    else driver_.resume();
}

RenderJob ViewModel::compose(const JobInputs& inputs) const {
    RenderJob job = inputs.scene->renders[inputs.render_index];
    apply_option_tokens(job.options, config_.option_tokens);
    inputs.overrides.merge(CausticKnobs::from(job.options), inputs.person_knobs).apply(job.options);
    // The classic integrator has no passes to limit.
    if (job.options.integrator == IntegratorKind::progressive) stop_rules_for(job, job.options).apply(job.options);
    if (inputs.threads >= 0) job.options.threads = inputs.threads;
    int width = job.width, height = job.height;
    if (job.options.resolution_override > 0) width = height = job.options.resolution_override;
    job.options.resolution_override = 0;
    job.width = std::max(1, static_cast<int>(std::lround(width * inputs.resolution_scale)));
    job.height = std::max(1, static_cast<int>(std::lround(height * inputs.resolution_scale)));
    job.camera = orbit_.desc();
    return job;
}

RenderJob ViewModel::current_job() const { return scene_ ? compose(inputs_) : RenderJob{}; }

// --- the frame

void ViewModel::update() {
    if (std::optional<LoadedScene> loaded = source_.poll()) install(std::move(*loaded));
    else if (!source_.loading() && !watched_path_.empty() && source_.changed_on_disk()) reload();

    if (dirty_ && scene_) {
        try {
            driver_.request(compose(inputs_));
            requested_inputs_ = inputs_;
        } catch (const std::exception& e) {
            error_ = e.what();
        }
        dirty_ = false;
    }
    driver_.update();
    if (driver_.restarts() != seen_restarts_) {
        seen_restarts_ = driver_.restarts();
        running_inputs_ = requested_inputs_;
    }
    if (std::optional<std::string> failure = driver_.take_error()) {
        // A render that fails to prepare (e.g. a material that breaks the photon roulette) puts
        // back the last inputs that rendered; the image of that render stays on screen.
        error_ = *failure;
        const bool reverted = committed_inputs_ && running_inputs_ && !same_inputs(*committed_inputs_, *running_inputs_);
        if (reverted) {
            inputs_ = *committed_inputs_;
            scene_ = inputs_.scene;
            scene_path_ = inputs_.scene_path;
            mark_dirty();
        }
        running_inputs_.reset();
    } else if (running_inputs_ && driver_.has_job() && (driver_.progress().prepared || driver_.progress().finished)) {
        committed_inputs_ = running_inputs_;  // prepared without error (photons included)
    }
    resolve_target();
    update_overlay();
}

// --- overlay

void ViewModel::set_overlay(const OverlaySettings& settings) { overlay_ = settings; }

void ViewModel::update_overlay() {
    if (!overlay_.enabled) return;
    bool reproject = false;
    if (overlay_trace_.valid()) {
        if (overlay_trace_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
        overlay_world_ = overlay_trace_.get();
        reproject = true;
    }
    const std::vector<LightProjectionMap>& maps = driver_.projection_maps();
    if (!maps.empty() && (overlay_.light < 0 || overlay_.light >= static_cast<int>(maps.size()))) overlay_.light = 0;
    if (driver_.maps_version() != traced_maps_version_ || !(overlay_ == traced_settings_) || overlay_stale_) {
        traced_maps_version_ = driver_.maps_version();
        traced_settings_ = overlay_;
        overlay_stale_ = false;
        if (overlay_.light >= 0 && overlay_.light < static_cast<int>(maps.size())) {
            // Tracing the map costs a ray per boundary corner and occupied cell: off the UI thread.
            const RenderSession* session = &driver_.session();
            overlay_trace_ = std::async(std::launch::async, [map = maps[overlay_.light], cells = overlay_.cells, session] {
                return trace_overlay(map, [session](const Ray& ray, glm::vec3& p) { return session->pick(ray, p); }, cells);
            });
            return;
        }
        overlay_world_.reset();
        overlay_image_ = {};
        ++overlay_version_;
        return;
    }
    if (!overlay_world_ || !driver_.has_job()) return;
    const RenderJob& job = driver_.job();  // the image on screen is this job's
    if (reproject || !same_camera(job.camera, projected_camera_) || job.width != projected_width_ ||
        job.height != projected_height_) {
        const RenderSession* session = &driver_.session();
        overlay_image_ = project_overlay(*overlay_world_, Camera(job.camera, job.width, job.height), glm::vec3(job.camera.eye),
                                         [session](const Ray& ray, glm::vec3& p) { return session->pick(ray, p); });
        projected_camera_ = job.camera;
        projected_width_ = job.width;
        projected_height_ = job.height;
        ++overlay_version_;
    }
}

bool ViewModel::overlay_settled() const {
    if (!overlay_.enabled) return true;
    return driver_.maps_final() && !overlay_trace_.valid() && traced_maps_version_ == driver_.maps_version() &&
           overlay_ == traced_settings_ && !overlay_stale_;
}

std::string ViewModel::overlay_note() const {
    if (!overlay_.enabled || !scene_) return {};
    const RenderJob job = current_job();
    if (job.options.caustic_num_photons <= 0) return "photons are off: set Photons above 0 to build projection maps";
    if (job.options.projection_map == ProjectionMapMode::off) return "projection maps are off";
    const std::vector<LightProjectionMap>& maps = driver_.projection_maps();
    if (maps.empty())
        return driver_.maps_final() ? "no light has a projection map (only lights with quadratic falloff shoot photons)"
                                    : "the map is shown once the render has finished (progressive: its first pass)";
    if (overlay_.light >= static_cast<int>(maps.size())) return "no such light";
    if (overlay_trace_.valid()) return "tracing the map onto the scene...";
    if (!overlay_world_) return {};
    return std::to_string(overlay_world_->outline.size() / 2) + " outline segments, " +
           std::to_string(overlay_world_->cells.size()) + " cells on the scene";
}

// --- saving

std::string ViewModel::default_save_path() const {
    if (!scene_) return "preview.png";
    const std::string& output = scene_->renders[inputs_.render_index].output;
    return output.empty() ? "preview.png" : output;
}

SaveResult ViewModel::save(const std::string& path, bool overwrite) {
    if (!driver_.has_job()) return {SaveOutcome::failed, "nothing rendered yet"};
    const SessionProgress& progress = driver_.accumulation().accumulating ? driver_.accumulation() : driver_.progress();
    return save_preview_png(path, driver_.image(), driver_.job(), scene_path_, progress, overwrite);
}

}  // namespace caustica::ui
