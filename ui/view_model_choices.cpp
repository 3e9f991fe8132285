// The person's choices in the ViewModel (knobs, preset, undo and redo, --a4, resolution, threads,
// stopping rules), what differs from `caustica render`, and the command line that renders the same.
#include "ui/view_model.h"

#include "core/integrators/registry.h"

#include "core/io/image_io.h"
#include "core/photons/photon_tracer.h"
#include "core/render/accumulation_state.h"
#include "ui/saved_accumulation.h"
#include "core/scene/source_location.h"
#include "core/util/printable_text.h"
#include "ui/view_model_internal.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace caustica::ui {
namespace {

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

std::string describe_rules(const StopRules& r) {
    if (r.passes == 0 && r.time_limit <= 0.0 && r.target_error <= 0.0) return "refine until paused";
    std::string text;
    auto add = [&](const std::string& part) { text += (text.empty() ? "" : ", ") + part; };
    if (r.passes > 0) add(std::to_string(r.passes) + (r.passes == 1 ? " pass" : " passes"));
    if (r.time_limit > 0.0) add(exact_number(r.time_limit) + " s");
    if (r.target_error > 0.0) add(exact_number(100.0 * r.target_error) + "% error");
    return text;
}
}  // namespace

long long photon_memory_limit() {
    // check_photon_memory's budget when the scene itself takes next to nothing.
    const double limit = std::floor(default_render_memory_bytes() / photon_memory_bound(1.0));
    return static_cast<long long>(std::clamp(limit, 0.0, 100e9));  // --caustic-num-photons' own range ends at 1e11
}

std::string shell_quote(const std::string& word) {
    if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=./,:@%") ==
                             std::string::npos)
        return word;
    std::string quoted = "'";
    for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
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
    if (display_.tonemap && *display_.tonemap != job.options.tonemap)  // a saved PNG takes the curve shown
        all.push_back({"tonemap", "tone curve", tonemap_name(job.options.tonemap), tonemap_name(*display_.tonemap), ""});
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
    } else if (id == "tonemap") {
        display_.tonemap.reset();
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
    if (job.options.reproducible && !before.reproducible) tokens.push_back("--reproducible");  // the preview's seeds
    if (job.options.threads != before.threads) tokens.insert(tokens.end(), {"--threads", std::to_string(job.options.threads)});
    if (display_.tonemap && *display_.tonemap != job.options.tonemap)
        tokens.insert(tokens.end(), {"--tonemap", tonemap_name(*display_.tonemap)});
    return tokens;
}

std::string ViewModel::command_output() const {
    // Never the image the preview saved last: the command would overwrite it.
    const std::string saved = last_saved_.empty() ? std::string() : absolute_path(last_saved_);
    const std::string proposed = default_save_path();
    if (saved.empty() || absolute_path(proposed) != saved) return proposed;
    const std::filesystem::path path(proposed);
    return (path.parent_path() / (path.stem().string() + "-render" + path.extension().string())).string();
}

std::string ViewModel::command_line() const {
    if (!scene_) return {};
    std::string text = "caustica render " + shell_quote(scene_path_);
    for (const std::string& folder : config_.allow_read) text += " --allow-read " + shell_quote(folder);  // the scene may need them
    for (const std::string& t : inputs_.tokens) text.append(" ").append(shell_quote(t));
    for (const std::string& t : person_tokens()) text.append(" ").append(shell_quote(t));
    const std::string output = command_output();
    // "PNG: apply the display exposure" saves the display's stops too (ViewModel::save).
    const RenderJob job = current_job();
    if (display_.exposure_to_png && display_.exposure != 0.0f && image_format_of(output) == ImageFormat::png)
        text += " --exposure " + exact_number(job.options.exposure + display_.exposure);
    return text + " -o " + shell_quote(output);
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
        // The copied command writes beside the saved image; continuing the state saved with it
        // (while the job is still the one saved) means writing the saved image itself.
        if (saved_state_key_ && !last_saved_.empty() && *saved_state_key_ == key_without_scene(job))
            notes.push_back("to continue the accumulation saved with " + printable_text(last_saved_) +
                            ": add --resume and write -o " + shell_quote(last_saved_) +
                            " (it replaces that image; --passes, --time and --target-error count from its start)");
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

}  // namespace caustica::ui
