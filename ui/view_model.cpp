#include "ui/view_model.h"

#include "core/integrators/registry.h"

#include "core/photons/photon_tracer.h"
#include "core/scene/camera.h"
#include "core/scene/scene_flatten.h"
#include "core/scene/source_location.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

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
    return settings;  // no preset of its own: the scene starts as `caustica render SCENE` renders it
}

/// Whether option tokens set a progressive stopping rule (any value, --passes 1 too).
bool sets_stop_rules(const std::vector<std::string>& tokens) {
    Options probe;
    probe.passes = -1;  // values no token can give
    probe.time_limit = probe.target_error = -1.0;
    apply_option_tokens(probe, tokens);
    return probe.passes != -1 || probe.time_limit != -1.0 || probe.target_error != -1.0;
}

bool sets_stop_rules_safely(const std::vector<std::string>& tokens) {
    try {
        return sets_stop_rules(tokens);
    } catch (const std::exception&) {
        return false;  // compose() reports bad tokens
    }
}

std::string absolute_path(const std::string& path) {
    std::error_code ec;
    const std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(path), ec);
    return ec ? path : p.string();
}

std::string describe_rules(const StopRules& r) {
    if (r.passes == 0 && r.time_limit <= 0.0 && r.target_error <= 0.0) return "refine until paused";
    std::string text;
    auto add = [&](const std::string& part) { text += (text.empty() ? "" : ", ") + part; };
    if (r.passes > 0) add(std::to_string(r.passes) + (r.passes == 1 ? " pass" : " passes"));
    if (r.time_limit > 0.0) add(exact_number(r.time_limit) + " s");
    if (r.target_error > 0.0) add(exact_number(100.0 * r.target_error) + "% error");
    return text;
}

bool has_token(const std::vector<std::string>& tokens, const std::string& token) {
    return std::find(tokens.begin(), tokens.end(), token) != tokens.end();
}

}  // namespace

long long photon_memory_limit() {
    const double physical = static_cast<double>(::sysconf(_SC_PHYS_PAGES)) * static_cast<double>(::sysconf(_SC_PAGE_SIZE));
    const double limit = std::floor(0.6 * physical / photon_memory_bound(1.0));  // check_photon_memory's budget
    return static_cast<long long>(std::clamp(limit, 0.0, 100e9));  // --caustic-num-photons' own range ends at 1e11
}

std::string camera_lua(const CameraDesc& c) {
    auto v = [](glm::dvec3 p) { return "{" + exact_number(p.x) + ", " + exact_number(p.y) + ", " + exact_number(p.z) + "}"; };
    return v(c.eye) + ", " + v(c.view) + ", " + v(c.up) + ", " + exact_number(c.fovy_degrees);
}

std::string shell_quote(const std::string& word) {
    if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=./,:@%") ==
                             std::string::npos)
        return word;
    std::string quoted = "'";
    for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

ViewModel::ViewModel(ModelConfig config)
    : config_(std::move(config)),
      source_(load_settings(config_), config_.recent_file),
      driver_(config_.driver),
      bookmarks_(bookmarks_file_beside(config_.recent_file)) {}

ViewModel::~ViewModel() {
    if (overlay_trace_.valid()) overlay_trace_.wait();
}

// --- scenes

void ViewModel::open(const std::string& path) {
    std::string extension = std::filesystem::path(path).extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
    if (extension != ".lua") {  // an image or mesh would run as Lua and fail with a baffling syntax error
        error_ = path + ": not a scene script (scenes are .lua files)";
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
        inputs_.tokens = tokens_of(scene_path_);  // the view's options belong to the scene they were given for
        forget_choices();  // another scene starts as `caustica render` renders it (its own knobs and scales)
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

Options ViewModel::base_options(const JobInputs& inputs, bool with_preset) const {
    Options options = inputs.scene->renders[inputs.render_index].options;
    apply_option_tokens(options, inputs.tokens);
    if (with_preset && !inputs.preset.empty()) apply_option_tokens(options, {"--quality", inputs.preset});
    return options;
}

CausticKnobs ViewModel::script_knobs(const JobInputs& inputs) const {
    if (!inputs.scene) return {};
    return CausticKnobs::from(base_options(inputs, true));
}

CausticKnobs ViewModel::effective_knobs(const JobInputs& inputs) const {
    return inputs.overrides.merge(script_knobs(inputs), inputs.person_knobs);
}

CausticKnobs ViewModel::knobs() const { return effective_knobs(inputs_); }

bool ViewModel::same_inputs(const JobInputs& a, const JobInputs& b) const {
    return a.scene == b.scene && a.render_index == b.render_index && a.tokens == b.tokens && a.preset == b.preset &&
           effective_knobs(a) == effective_knobs(b) && a.threads == b.threads && a.resolution_scale == b.resolution_scale;
}

void ViewModel::set_knobs(const CausticKnobs& knobs) {
    const CausticKnobs current = this->knobs();
    if (knobs == current) return;
    record_undo();
    inputs_.overrides.record(current, knobs);
    inputs_.person_knobs = knobs;
    mark_dirty();
}

void ViewModel::reset_knobs() {
    if (!inputs_.overrides.any()) return;
    record_undo();
    inputs_.overrides.clear();
    mark_dirty();
}

void ViewModel::set_preset(const std::string& name) {
    if (name == inputs_.preset) return;
    if (!name.empty()) {
        Options probe;
        apply_option_tokens(probe, {"--quality", name});  // throws for an unknown name
    }
    record_undo();
    inputs_.preset = name;
    mark_dirty();
}

// --- choices, undo and redo

Choices ViewModel::choices() const { return {inputs_.person_knobs, inputs_.overrides, inputs_.preset, person_stop_rules_}; }

void ViewModel::restore(const Choices& c) {
    const StopRules rules_before = stop_rules();
    inputs_.person_knobs = c.person_knobs;
    inputs_.overrides = c.overrides;
    inputs_.preset = c.preset;
    person_stop_rules_ = c.stop_rules;
    if (stop_rules() != rules_before) driver_.set_stop_rules(stop_rules());
    mark_dirty();
}

void ViewModel::record_undo() {
    if (coalescing_ && group_open_) return;  // one drag, one step
    undo_.push_back(choices());
    if (undo_.size() > 200) undo_.erase(undo_.begin());
    redo_.clear();
    group_open_ = coalescing_;
}

void ViewModel::set_coalescing(bool on) {
    coalescing_ = on;
    if (!on) group_open_ = false;
}

void ViewModel::undo() {
    if (undo_.empty()) return;
    redo_.push_back(choices());
    const Choices previous = undo_.back();
    undo_.pop_back();
    group_open_ = false;
    restore(previous);
}

void ViewModel::redo() {
    if (redo_.empty()) return;
    undo_.push_back(choices());
    const Choices next = redo_.back();
    redo_.pop_back();
    group_open_ = false;
    restore(next);
}

void ViewModel::forget_choices() {
    inputs_.person_knobs = {};
    inputs_.overrides.clear();
    inputs_.preset.clear();
    person_stop_rules_.reset();
    undo_.clear();
    redo_.clear();
    group_open_ = false;
}

// --- what differs from `caustica render`

Options ViewModel::scene_options() const { return scene_ ? base_options(inputs_, false) : Options{}; }

std::vector<Difference> ViewModel::differences() const {
    std::vector<Difference> all;
    if (!scene_) return all;
    const RenderJob& script_job = scene_->renders[inputs_.render_index];
    if (!inputs_.preset.empty()) all.push_back({"preset", "quality preset", "none", inputs_.preset, ""});
    const CausticKnobs base = script_knobs(inputs_), shown = knobs();
    for (KnobField field : all_knob_fields)
        if (knob_differs(shown, base, field)) {
            Difference d{"knob:" + std::to_string(static_cast<std::uint32_t>(field)), knob_label(field),
                         knob_value_text(base, field), knob_value_text(shown, field), ""};
            if (knob_tokens(shown, base, field).empty()) d.note = "no command-line option sets this back";
            all.push_back(d);
        }
    RenderJob job;
    try {
        job = current_job();
    } catch (const std::exception&) {
        return all;  // bad options: the error banner says why
    }
    if (integrator_entry(job.options.integrator).accumulates) {
        Options scene_opts = base_options(inputs_, true);
        shown.apply(scene_opts);
        const StopRules render_rules = StopRules::of(scene_opts), rules = StopRules::of(job.options);
        if (!(render_rules == rules)) {
            Difference d{"stop", "stopping rules", describe_rules(render_rules), describe_rules(rules), ""};
            if (!person_stop_rules_) d.note = "the preview refines until paused unless a rule is given";
            all.push_back(d);
        }
    }
    if (inputs_.threads >= 0 && inputs_.threads != base_options(inputs_, true).threads)
        all.push_back({"threads", "threads", std::to_string(base_options(inputs_, true).threads),
                       std::to_string(inputs_.threads), ""});
    if (inputs_.resolution_scale != 1.0) {
        const int w = job.width, h = job.height;
        const double s = inputs_.resolution_scale;
        all.push_back({"resolution", "resolution",
                       std::to_string(std::lround(w / s)) + " x " + std::to_string(std::lround(h / s)),
                       std::to_string(w) + " x " + std::to_string(h), "no command-line option renders at this size"});
    }
    if (orbit_.moved())
        all.push_back({"camera", "camera", "as scripted", "orbited",
                       "no command-line option sets the camera: Copy camera gives the gr.render arguments"});
    (void)script_job;
    return all;
}

void ViewModel::reset_difference(const std::string& id) {
    if (!scene_) return;
    if (id == "all") {
        // One undo step for the whole reset, and none when there is nothing to undo. Mid-drag the
        // drag's own step is closed first: record_undo() would otherwise add nothing.
        const std::vector<Difference> all = differences();
        if (std::any_of(all.begin(), all.end(), [](const Difference& d) { return d.id != "camera"; })) {
            group_open_ = false;
            record_undo();
        }
        const bool saved = coalescing_;
        coalescing_ = group_open_ = true;  // the steps below belong to this one
        for (const Difference& d : differences())
            if (d.id != "camera") reset_difference(d.id);
        coalescing_ = saved;
        group_open_ = false;
        return;
    }
    if (id == "preset") {
        set_preset("");
    } else if (id.rfind("knob:", 0) == 0) {
        record_undo();
        inputs_.overrides.clear(static_cast<KnobField>(std::stoul(id.substr(5))));
        mark_dirty();
    } else if (id == "stop") {
        Options scene_opts = base_options(inputs_, true);
        knobs().apply(scene_opts);
        set_stop_rules(StopRules::of(scene_opts));
    } else if (id == "threads") {
        inputs_.threads = -1;
        mark_dirty();
    } else if (id == "resolution") {
        set_resolution_scale(1.0);
    } else if (id == "camera") {
        reset_camera();
    }
}

std::vector<std::string> ViewModel::person_tokens() const {
    std::vector<std::string> tokens;
    if (!scene_) return tokens;
    if (!inputs_.preset.empty()) tokens.insert(tokens.end(), {"--quality", inputs_.preset});
    const CausticKnobs base = script_knobs(inputs_), shown = knobs();
    for (KnobField field : all_knob_fields) {
        const std::vector<std::string> t = knob_tokens(shown, base, field);
        tokens.insert(tokens.end(), t.begin(), t.end());
    }
    const RenderJob job = current_job();
    Options before = base_options(inputs_, true);
    shown.apply(before);
    if (integrator_entry(job.options.integrator).accumulates) {
        const StopRules render_rules = StopRules::of(before), rules = StopRules::of(job.options);
        const bool endless = rules.passes == 0 && rules.time_limit <= 0.0 && rules.target_error <= 0.0;
        if (endless) {  // render refuses an endless run: the passes shown so far
            const int shown_passes = std::max(1, driver_.accumulation().passes_done);
            if (shown_passes != render_rules.passes) tokens.insert(tokens.end(), {"--passes", std::to_string(shown_passes)});
        } else {
            if (rules.passes != render_rules.passes) tokens.insert(tokens.end(), {"--passes", std::to_string(rules.passes)});
            if (rules.time_limit != render_rules.time_limit)
                tokens.insert(tokens.end(), {"--time", exact_number(rules.time_limit)});
            if (rules.target_error != render_rules.target_error)
                tokens.insert(tokens.end(), {"--target-error", exact_number(rules.target_error)});
        }
    }
    if (job.options.threads != before.threads) tokens.insert(tokens.end(), {"--threads", std::to_string(job.options.threads)});
    return tokens;
}

std::string ViewModel::command_line() const {
    if (!scene_) return {};
    std::string text = "caustica render " + shell_quote(scene_path_);
    for (const std::string& folder : config_.allow_read) text += " --allow-read " + shell_quote(folder);  // the scene may need them
    for (const std::string& t : inputs_.tokens) text += " " + shell_quote(t);
    for (const std::string& t : person_tokens()) text += " " + shell_quote(t);
    return text;
}

std::vector<std::string> ViewModel::command_line_notes() const {
    std::vector<std::string> notes;
    for (const Difference& d : differences())
        if (!d.note.empty() && d.id != "stop") notes.push_back(d.label + ": " + d.note);
    if (render_count() > 1)
        notes.push_back("the command renders every gr.render call of the script; this is call " +
                        std::to_string(inputs_.render_index + 1));
    if (scene_) {
        const RenderJob job = current_job();
        const StopRules rules = StopRules::of(job.options);
        if (integrator_entry(job.options.integrator).accumulates && rules.passes == 0 && rules.time_limit <= 0.0 &&
            rules.target_error <= 0.0)
            notes.push_back("the preview refines until paused; the command renders the passes shown so far");
    }
    return notes;
}

std::string ViewModel::a4_origin() const {
    if (!scene_) return {};
    const RenderJob& script_job = scene_->renders[inputs_.render_index];
    if (const SourceLocation* where = script_job.option_origin("a4"))
        return "gr.option in the script (" + where->file + ":" + std::to_string(where->line) + ")";
    if (script_job.options.a4) return "the script";
    if (!has_token(inputs_.tokens, "--a4")) return {};
    const bool from_command_line = has_token(config_.option_tokens, "--a4") &&
                                   (config_.option_scene.empty() ? scene_tokens_.front().first == absolute_path(scene_path_)
                                                                 : same_file(config_.option_scene, scene_path_));
    return from_command_line ? "the command line" : "ticked here";
}

void ViewModel::set_a4(bool on) {
    if (!scene_ || scene_->renders[inputs_.render_index].options.a4) return;  // the script's gr.option sets it
    std::vector<std::string>& stored = tokens_of(scene_path_);
    if (on == has_token(stored, "--a4")) return;
    if (on) stored.push_back("--a4");
    else std::erase(stored, std::string("--a4"));
    inputs_.tokens = stored;
    update_a4_hint();
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
    const bool given = sets_stop_rules_safely(inputs_.tokens) || script_job.option_origin("passes") ||
                       script_job.option_origin("time") || script_job.option_origin("target-error");
    return given ? StopRules::of(options) : StopRules{};  // none given: refine until paused
}

StopRules ViewModel::stop_rules() const {
    if (!scene_ || person_stop_rules_) return person_stop_rules_.value_or(StopRules{});
    const RenderJob& script_job = scene_->renders[inputs_.render_index];
    Options options = script_job.options;
    try {
        apply_option_tokens(options, inputs_.tokens);
    } catch (const std::exception&) {
        // compose() reports bad tokens
    }
    return stop_rules_for(script_job, options);
}

void ViewModel::set_stop_rules(const StopRules& rules) {
    if (rules == stop_rules()) return;
    record_undo();
    person_stop_rules_ = rules;
    driver_.set_stop_rules(rules);  // the job to come carries them too (compose)
}

void ViewModel::set_paused(bool paused) {
    if (paused) driver_.pause();
    else driver_.resume();
}

RenderJob ViewModel::compose(const JobInputs& inputs) const {
    // As `caustica render SCENE [tokens]` does (app/render_command.cpp): the command line's options
    // over the script's gr.option, then what the person picked, as the options Copy command line adds.
    RenderJob job = inputs.scene->renders[inputs.render_index];
    job.apply_command_line(inputs.tokens);  // exactly as app/render_command.cpp
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
    const std::string absolute = absolute_path(path);
    std::optional<SaveToneSettings> tone;  // none: the job's --tonemap and --exposure, as `render` writes
    if (display_.exposure_to_png && image_format_of(path) == ImageFormat::png)  // EXR and PFM stay linear
        tone = SaveToneSettings{driver_.job().options.tonemap,
                                static_cast<float>(driver_.job().options.exposure + display_.exposure)};
    SaveResult result = save_preview_image(absolute, driver_.image(), driver_.job(), scene_path_, progress, overwrite, tone);
    if (result.outcome == SaveOutcome::written) last_saved_ = absolute;
    return result;
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

void ViewModel::go_to_camera(const CameraDesc& camera) {
    if (!scene_) return;
    const CameraDesc& script = scene_->renders[inputs_.render_index].camera;
    if (same_camera(camera, script)) {
        orbit_ = OrbitCamera(script, default_target_distance(script));
        target_known_ = false;
    } else {  // a moved camera: it stays on a reload, and the first surface on its axis becomes the target
        CameraDesc moved = script;
        moved.eye = camera.eye;
        moved.view = camera.view;
        moved.up = camera.up;
        orbit_ = OrbitCamera(moved, default_target_distance(moved));
        orbit_.set_target(orbit_.target());
        target_known_ = false;
    }
    mark_dirty();
}

std::string ViewModel::photons_note() const {
    const PreviewDriver& driver = driver_;
    if (!driver.has_job() || (!driver.progress().finished && !driver.accumulation().accumulating)) return {};
    const Options& o = driver.job().options;
    if (o.caustic_num_photons <= 0 || o.no_caustic_map) return {};
    const RenderStats& stats = driver.stats();
    if (stats.caustic_photons > 0) return {};
    const std::string requested = "requested " + std::to_string(o.caustic_num_photons) + " photons, none ";
    long long traced = 0, candidates = 0;
    for (const LightCausticStats& c : stats.caustic_lights) traced += c.traced, candidates += c.candidates;
    if (stats.caustic_lights.empty() || candidates == 0)
        return requested + "shot: no light shoots photons (only lights with quadratic falloff do)";
    if (traced == 0) return requested + "shot: the projection maps found no specular object in any light's view";
    return requested + "stored: no photon reached a diffuse surface through a specular object";
}

// --- course scenes

namespace {

/// How many of the flattened objects have their origin inside the camera's view.
int objects_in_view(const FlatScene& flat, const RenderJob& job) {
    const CameraDesc& c = job.camera;
    const glm::dvec3 forward = glm::normalize(c.view);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, c.up));
    const glm::dvec3 up = glm::cross(right, forward);
    const double tan_y = std::tan(glm::radians(vertical_fov_degrees(c, job.width, job.height)) * 0.5);
    const double tan_x = tan_y * job.width / std::max(1, job.height);
    auto inside = [&](const glm::dmat4& to_world) {
        const glm::dvec3 d = glm::dvec3(to_world[3]) - c.eye;
        const double z = glm::dot(d, forward);
        return z > 0.0 && std::abs(glm::dot(d, right)) <= 1.1 * tan_x * z && std::abs(glm::dot(d, up)) <= 1.1 * tan_y * z;
    };
    int count = 0;
    for (const PlacedPrimitive& p : flat.primitives) count += inside(p.object_to_world) ? 1 : 0;
    for (const FlatCsgObject& o : flat.csg_objects)
        for (const PlacedPrimitive& p : o.leaves) count += inside(p.object_to_world) ? 1 : 0;
    return count;
}

}  // namespace

namespace {

/// Objects of the first render in view under the original's and the course's conventions (-1: that
/// convention cannot flatten the scene), and how many objects there are.
struct ViewCounts {
    int seed = -1, course = -1;
    std::size_t objects = 0;
};

std::optional<ViewCounts> count_in_view(const SceneScript& script) {
    if (script.renders.empty()) return std::nullopt;
    const RenderJob& job = script.renders.front();
    if (!job.scene || job.scene->nodes.size() > 100'000) return std::nullopt;  // runs on the UI thread: keep it cheap
    ViewCounts counts;
    for (bool course : {false, true}) {
        try {
            const FlatScene flat = flatten_scene(*job.scene, job.root, course);
            (course ? counts.course : counts.seed) = objects_in_view(flat, job);
            counts.objects = flat.primitives.size();
            for (const FlatCsgObject& o : flat.csg_objects) counts.objects += o.leaves.size();
        } catch (const std::exception&) {
            // e.g. a transform singular in one order only: the other convention is the one
        }
    }
    return counts;
}

}  // namespace

std::string course_scene_hint(const SceneScript& script) {
    // Our own scenes keep at least as many objects in view in their (seed) conventions as in the
    // course's; the course scenes measured (../shared/cs488 with meshes) lose some without --a4.
    const std::optional<ViewCounts> c = count_in_view(script);
    if (!c || c->course < 0 || c->course <= c->seed) return {};
    return "Looks like a course (CS488 A4) scene: " + std::to_string(c->course) + " of " + std::to_string(c->objects) +
           " objects are in view with --a4, " + std::to_string(std::max(0, c->seed)) +
           " without. Tick --a4 if it renders broken.";
}

std::string seed_scene_hint(const SceneScript& script) {
    const std::optional<ViewCounts> c = count_in_view(script);
    if (!c || c->seed < 0 || c->seed <= c->course) return {};
    return "Looks like a scene in the original's conventions: " + std::to_string(c->seed) + " of " +
           std::to_string(c->objects) + " objects are in view without --a4, " + std::to_string(std::max(0, c->course)) +
           " with. Untick --a4 if it renders broken.";
}

void ViewModel::update_a4_hint() {
    a4_hint_.clear();
    if (!scene_ || scene_->renders[inputs_.render_index].options.a4) return;  // the script's choice: no checkbox
    a4_hint_ = has_token(inputs_.tokens, "--a4") ? seed_scene_hint(*scene_) : course_scene_hint(*scene_);
}

}  // namespace caustica::ui
