// The ViewModel's scenes, the job it composes, the per-frame step, the overlay and saving; its
// camera, choices and hints are in ui/view_model_camera.cpp, _choices.cpp and _hints.cpp.
#include "ui/view_model.h"

#include "core/integrators/registry.h"

#include "core/scene/camera.h"
#include "core/util/printable_text.h"
#include "ui/view_model_internal.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace caustica::ui {
namespace {

LoadSettings load_settings(const ModelConfig& config) {
    LoadSettings settings;
    settings.timeout_seconds = config.script_timeout;
    settings.memory_limit_bytes = config.script_memory_bytes;
    settings.allow_read = config.allow_read;
    settings.output_given = true;  // the script's names are only Save's proposal, checked when saved (save)
    return settings;  // no preset of its own: the scene starts as `caustica render SCENE` renders it
}

}  // namespace

ViewModel::ViewModel(ModelConfig config)
    : config_(std::move(config)),
      source_(load_settings(config_), config_.recent_file),
      driver_(config_.driver),
      bookmarks_(bookmarks_file_beside(config_.recent_file)),
      integrators_(integrator_memory_beside(config_.recent_file)) {}

ViewModel::~ViewModel() {
    if (overlay_trace_.valid()) overlay_trace_.wait();
}

// --- scenes

void ViewModel::open(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
    if (extension != ".lua") {  // an image or mesh would run as Lua and fail with a baffling syntax error
        error_ = printable_text(path + ": not a scene script (scenes are .lua files)");
        return;
    }
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
    std::vector<std::string> all;
    if (scene_)
        for (const std::string& w : scene_->warnings) all.push_back(printable_text(w));
    for (const std::string& w : driver_.session().warnings()) all.push_back(printable_text(w));
    if (!integrators_.warning().empty()) all.push_back(printable_text(integrators_.warning()));
    return all;
}

void ViewModel::install(LoadedScene loaded) {
    const bool reloaded = same_file(loaded.path, scene_path_);
    if (!loaded.error.empty()) {  // the shown scene stays; the failed file is watched for a fix
        error_ = printable_text(loaded.error);
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
        inputs_.tokens = tokens_of(scene_path_);  // the view's options belong to the scene they were given for
        forget_choices();  // another scene starts as `caustica render` renders it (its own knobs and scales)
        recall_integrator();  // but with the integrator the person picked for it before
        if (!scheduled_save_.empty()) {  // it was meant for the previous scene's image
            scheduled_result_ = SaveResult{SaveOutcome::failed, scheduled_save_ + " not saved: another scene was opened"};
            scheduled_save_.clear();
        }
        driver_.forget_scene();  // its statistics, pass times and maps are not this scene's
        source_.add_recent(scene_path_);
    }
    inputs_.render_index = std::clamp(inputs_.render_index, 0, render_count() - 1);
    if (!reloaded || !orbit_.moved()) {
        const CameraDesc& camera = scene_->renders[inputs_.render_index].camera;
        orbit_ = OrbitCamera(camera, default_target_distance(camera));
        target_known_ = false;
    }
    watch_current();
    update_a4_hint();
    mark_dirty();
}

std::vector<std::string>& ViewModel::tokens_of(const std::string& path) {
    const std::string key = absolute_path(path);
    for (auto& [scene, tokens] : scene_tokens_)
        if (scene == key) return tokens;
    std::vector<std::string> tokens;
    if (!tokens_assigned_ && (config_.option_scene.empty() || same_file(config_.option_scene, path))) {
        tokens = config_.option_tokens;
        tokens_assigned_ = true;
    }
    scene_tokens_.emplace_back(key, std::move(tokens));
    return scene_tokens_.back().second;
}

void ViewModel::watch_current() {
    std::vector<std::string> dependencies;
    if (!error_.empty() && !watched_path_.empty()) {
        // The failed script may name a file that does not exist yet (a texture or mesh): its folder
        // changes when the file is created there, and so does a folder named in the message.
        const std::filesystem::path folder = std::filesystem::path(watched_path_).parent_path();
        dependencies.push_back(folder.empty() ? "." : folder.string());
        std::size_t at = 0;
        while ((at = error_.find_first_of("/.", at)) != std::string::npos) {
            std::size_t begin = error_.find_last_of(" '\"(:", at), end = error_.find_first_of(" '\"):,", at);
            begin = begin == std::string::npos ? 0 : begin + 1;
            const std::filesystem::path named = std::filesystem::path(error_.substr(begin, end - begin)).parent_path();
            if (!named.empty()) dependencies.push_back((named.is_absolute() ? named : folder / named).string());
            at = end == std::string::npos ? error_.size() : end;
        }
    }
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

// --- the job

RenderJob ViewModel::compose(const JobInputs& inputs) const {
    // As `caustica render SCENE [tokens]` does (app/render_plan.cpp): the command line's options
    // over the script's gr.option, then what the person picked, as the options Copy command line adds.
    RenderJob job = inputs.scene->renders[inputs.render_index];
    job.apply_command_line(inputs.tokens);  // exactly as app/render_plan.cpp
    if (!inputs.preset.empty()) apply_option_tokens(job.options, {"--quality", inputs.preset});
    inputs.overrides.merge(CausticKnobs::from(job.options), inputs.person_knobs).apply(job.options);
    // An integrator that does not accumulate has no passes to limit.
    if (integrator_entry(job.options.integrator).accumulates) stop_rules_for(job, job.options).apply(job.options);
    if (inputs.threads >= 0) job.options.threads = inputs.threads;
    int width = job.width, height = job.height;
    if (job.options.resolution_override > 0) width = height = job.options.resolution_override;
    job.options.resolution_override = 0;
    job.width = std::max(1, static_cast<int>(std::lround(width * inputs.resolution_scale)));
    job.height = std::max(1, static_cast<int>(std::lround(height * inputs.resolution_scale)));
    job.camera = orbit_.desc();
    // Seeded as --reproducible seeds, whatever the scene says: the copied command line (which adds
    // --reproducible) renders the same bits, and a job that comes back renders as it did.
    job.options.reproducible = true;
    return job;
}

RenderJob ViewModel::current_job() const { return scene_ ? compose(inputs_) : RenderJob{}; }

// --- the frame

void ViewModel::update() {
    if (std::optional<LoadedScene> loaded = source_.poll()) install(std::move(*loaded));
    else if (!source_.loading() && !watched_path_.empty() && source_.changed_on_disk()) reload();

    if (dirty_ && scene_) {
        try {
            const RenderJob job = compose(inputs_);
            clear_region_of_another_view(job);
            request_job(job);
            requested_inputs_ = inputs_;
        } catch (const std::exception& e) {
            error_ = printable_text(e.what());
        }
        dirty_ = false;
    }
    driver_.update();
    follow_saved_accumulations();
    if (driver_.restarts() != seen_restarts_) {
        seen_restarts_ = driver_.restarts();
        running_inputs_ = requested_inputs_;
    }
    if (std::optional<std::string> failure = driver_.take_error()) {
        // A render that fails to prepare (e.g. a material that breaks the photon roulette) puts
        // back the last inputs that rendered; the image of that render stays on screen.
        error_ = printable_text(*failure);
        if (!scheduled_save_.empty()) {  // it would wait for an end that will not come
            scheduled_result_ = SaveResult{SaveOutcome::failed, scheduled_save_ + " not saved: the render failed"};
            scheduled_save_.clear();
        }
        const bool reverted = committed_inputs_ && running_inputs_ && !same_inputs(*committed_inputs_, *running_inputs_);
        if (reverted) {
            inputs_ = *committed_inputs_;
            scene_ = inputs_.scene;
            scene_path_ = inputs_.scene_path;
            tokens_of(scene_path_) = inputs_.tokens;  // an --a4 that failed is untaken everywhere
            update_a4_hint();
            mark_dirty();
        }
        running_inputs_.reset();
    } else if (running_inputs_ && driver_.has_job() && (driver_.progress().prepared || driver_.progress().finished)) {
        committed_inputs_ = running_inputs_;  // prepared without error (photons included)
    }
    remember_integrator();
    resolve_target();
    update_overlay();
    if (!scheduled_save_.empty() && driver_.has_job() && !rendering()) {
        scheduled_result_ = save(scheduled_save_, scheduled_overwrite_);
        scheduled_save_.clear();
    }
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

// --- saving

std::string ViewModel::default_save_path() const {
    if (!scene_) return "preview.png";
    const std::string& output = scene_->renders[inputs_.render_index].output;
    return output.empty() ? "preview.png" : output;
}

SaveResult ViewModel::save(const std::string& path, bool overwrite) {
    if (!driver_.has_job()) return {SaveOutcome::failed, "nothing rendered yet"};
    const SessionProgress& progress = driver_.accumulation().accumulating ? driver_.accumulation() : driver_.progress();
    const std::string absolute = absolute_path(path);
    // A PNG takes the curve shown, and the display's exposure too when asked; EXR and PFM stay
    // linear (the job's --exposure only).
    std::optional<SaveToneSettings> tone;  // none: the job's --tonemap and --exposure, as `render` writes
    if (image_format_of(path) == ImageFormat::png) {
        const ViewTransform shown = view_transform();
        tone = SaveToneSettings{shown.tonemap, display_.exposure_to_png
                                                   ? shown.exposure_stops
                                                   : static_cast<float>(driver_.job().options.exposure)};
    }
    // The script's own name (what Save proposes) is written as `caustica render` writes it: only
    // inside the current folder (docs/RELIABILITY.md, section 1). Any other name is the user's.
    const bool script_named = path == driver_.job().output;
    const OutputPlace place = script_named ? OutputPlace::inside_current_folder : OutputPlace::anywhere;
    SaveResult result = save_preview_image(script_named ? path : absolute, driver_.image(), driver_.job(), scene_path_,
                                           progress, overwrite, tone, place);
    if (result.outcome == SaveOutcome::written) {
        last_saved_ = absolute;
        result.message += save_accumulation(script_named ? path : absolute, script_named);
    }
    return result;
}

ViewTransform ViewModel::view_transform() const {
    const Options* job = driver_.has_job() ? &driver_.job().options : nullptr;
    const Tonemap job_curve = job ? job->tonemap : Tonemap::clamp;
    const double job_exposure = job ? job->exposure : 0.0;
    return {display_.tonemap.value_or(job_curve), static_cast<float>(job_exposure + display_.exposure), display_.srgb};
}

bool ViewModel::rendering() const {
    return driver_.has_job() && (dirty_ || driver_.pending() || !driver_.progress().finished);
}

bool ViewModel::render_ends() const {
    const RenderJob job = scene_ ? current_job() : driver_.job();  // the rules to come count
    const StopRules r = StopRules::of(job.options);
    return !(integrator_entry(job.options.integrator).accumulates && r.passes == 0 && r.time_limit <= 0.0 &&
             r.target_error <= 0.0);
}

std::string ViewModel::passes_text() const {
    if (!driver_.has_job()) return "nothing rendered";
    const SessionProgress& a = driver_.accumulation();
    if (driver_.job().options.accumulates()) {
        const int done = a.accumulating ? a.passes_done : 0;
        return std::to_string(done) + (a.pass_limit > 0 ? " of " + std::to_string(a.pass_limit) : std::string()) +
               (done == 1 && a.pass_limit == 0 ? " pass" : " passes");
    }
    const SessionProgress& p = driver_.progress();
    if (p.finished) return "complete";
    if (p.showing_direct_light) return "direct light only, photons still being shot";
    const int tiles = p.tiles_total > 0 ? static_cast<int>(100.0 * p.tiles_done / p.tiles_total) : 0;
    return "pass " + std::to_string(std::min(p.pass + 1, std::max(1, p.passes))) + " of " +
           std::to_string(std::max(1, p.passes)) + ", " + std::to_string(tiles) + "% of its tiles";
}

void ViewModel::save_when_done(const std::string& path, bool overwrite) {
    scheduled_save_ = path;
    scheduled_overwrite_ = overwrite;
    scheduled_result_.reset();
}

std::optional<SaveResult> ViewModel::take_scheduled_result() {
    std::optional<SaveResult> result = std::move(scheduled_result_);
    scheduled_result_.reset();
    return result;
}

}  // namespace caustica::ui
