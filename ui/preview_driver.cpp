#include "ui/preview_driver.h"

#include "core/integrators/registry.h"

#include <algorithm>
#include <chrono>
#include <thread>
#include <utility>

namespace caustica::ui {
namespace {

double now_seconds() {
    using clock = std::chrono::steady_clock;
    return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

bool is_pass(const std::string& stage) {
    return stage == "preview" || stage == "first samples" || stage == "anti-aliasing";
}

std::size_t tiles_per_pass(const SessionProgress& p) {
    return p.passes > 0 ? p.tiles_total / static_cast<std::size_t>(p.passes) : 0;
}

constexpr std::size_t pass_history_length = 240;

}  // namespace

PreviewDriver::PreviewDriver(DriverSettings settings) : settings_(settings) {}

void PreviewDriver::request(const RenderJob& job) {
    pending_ = job;
    pending_saved_.reset();
}

void PreviewDriver::pause() {
    if (busy()) paused_ = true;  // advance() cancels the render
}

void PreviewDriver::resume() {
    if (!paused_) return;
    paused_ = false;
    resume_due_ = collected_ || cancel_sent_;  // else the pause has not stopped the render yet
}

void PreviewDriver::set_stop_rules(const StopRules& rules) {
    if (pending_) rules.apply(pending_->options);
    if (!started_ || !integrator_entry(job_.options.integrator).accumulates) return;
    if (StopRules::of(job_.options) == rules && !new_rules_) return;
    new_rules_ = rules;
}

void PreviewDriver::set_region(const RenderRegion& region) {
    if (region == region_) return;
    region_ = region;
    new_region_ = true;
}

bool PreviewDriver::maps_final() const {
    if (pending_ || !started_) return false;
    if (collected_ && progress_.finished) return true;
    // (A kept accumulation put back shows its passes before its photon stage is built again.)
    return job_.options.accumulates() && accumulation_.passes_done >= 1 && progress_.prepared;
}

bool PreviewDriver::first_full_pass_done() const {
    if (pending_ || !started_) return false;
    if (progress_.finished) return true;
    if (job_.options.accumulates()) return accumulation_.passes_done >= 1;
    const std::size_t per_pass = tiles_per_pass(progress_);
    const std::size_t full = per_pass * (settings_.coarse_preview ? 2 : 1);
    return per_pass > 0 && progress_.tiles_done >= full && progress_.passes >= (settings_.coarse_preview ? 2 : 1);
}

std::optional<std::string> PreviewDriver::take_error() {
    std::optional<std::string> e;
    e.swap(error_);
    return e;
}

void PreviewDriver::update() {
    // Forget the tiles the last update reported; keep those poll() copied since then.
    changed_.erase(changed_.begin(), changed_.begin() + static_cast<std::ptrdiff_t>(reported_));
    changed_generations_.erase(changed_generations_.begin(),
                               changed_generations_.begin() + static_cast<std::ptrdiff_t>(reported_));
    size_changed_ = false;
    advance(true);
    fetch();
    reported_ = changed_.size();
    const double now = now_seconds();
    if (busy() && now - stats_polled_at_ > 0.1) {
        poll_stats();
        stats_polled_at_ = now;
    }
}

void PreviewDriver::poll() {
    if (pending_) advance(false);
}

void PreviewDriver::take_progress() {
    progress_ = session_.progress();
    if (!progress_.accumulating) return;
    // A resumed render reports its pass count at once, its samples and radius after its first pass.
    if (progress_.samples_per_pixel == 0.0 && progress_.passes_done > 0 && accumulation_.accumulating) {
        progress_.samples_per_pixel = accumulation_.samples_per_pixel;
        progress_.radius = accumulation_.radius;
    }
    // The stages sum the progressive passes: their times for the plot come from the pass count.
    // A render's first snapshot only starts the clock (a resumed one counts its cut pass as done).
    const double now = now_seconds();
    if (progress_.generation != clock_generation_) {
        clock_generation_ = progress_.generation;
        pass_clock_ = now;
    } else if (progress_.passes_done > accumulation_.passes_done) {
        const int passes = progress_.passes_done - accumulation_.passes_done;
        for (int i = 0; i < passes; ++i) record_pass("progressive pass", (now - pass_clock_) / passes);
        pass_clock_ = now;
    }
    accumulation_ = progress_;
}

void PreviewDriver::record_pass(const std::string& name, double seconds) {
    pass_history_.push_back({generation_, name, seconds});
    if (pass_history_.size() > pass_history_length) pass_history_.pop_front();
}

void PreviewDriver::advance(bool spin) {
    const double now = now_seconds();
    take_progress();
    drop_overtaken_accumulation();
    if (started_ && !collected_ && !progress_.running) collect();
    if (!collected_ && (pending_ || paused_ || new_rules_ || new_region_)) {
        // A render younger than max_preview_wait finishes its coarse preview first, so that the
        // view keeps up while the camera moves instead of restarting before anything is shown.
        // A pause or new stopping rules stop it at once.
        const std::size_t per_pass = tiles_per_pass(progress_);
        const bool preview_shown = per_pass > 0 && progress_.tiles_done >= per_pass;
        const bool due = paused_ || new_rules_ || new_region_ || preview_shown ||
                         now - started_at_ >= settings_.max_preview_wait_seconds;
        if (!cancel_sent_ && due) {
            session_.cancel();  // returns at once; the worker stops after its current tile
            cancel_sent_ = true;
        }
        if (cancel_sent_ && spin) {
            const double deadline = now + settings_.cancel_spin_seconds;
            while (session_.progress().running && now_seconds() < deadline)
                std::this_thread::sleep_for(std::chrono::microseconds(100));
            take_progress();
            if (!progress_.running) collect();
        }
    }
    if (collected_) {
        const bool region_changed = new_region_;
        if (new_region_) apply_region();
        if (new_rules_) apply_stop_rules();
        // The render goes on in the new region, unless paused (then when resumed), continued
        // already under new rules, or replaced by a new job.
        if (region_changed && !paused_ && !pending_ && started_ && collected_) continue_accumulation();
        if (pending_) restart();
        else if (resume_due_ && progress_.cancelled) continue_accumulation();  // not after an error or an end
        resume_due_ = false;
    }
    if (!maps_refreshed_ && !stats_forgotten_ && maps_final()) refresh_maps();
}

void PreviewDriver::forget_scene() {
    stats_forgotten_ = true;  // the session still holds the old render's until the next one starts
    kept_.reset();  // another scene: its jobs never come back
    stats_ = {};
    pass_history_.clear();
    computed_stages_.clear();
    if (!maps_.empty()) {
        maps_.clear();
        ++maps_version_;
    }
}

void PreviewDriver::poll_stats() {
    if (stats_forgotten_) return;
    stats_ = session_.stats();
    // The session keeps the last photon pass's numbers until this render's photon stage has run
    // (or reused them: "photon pass", cached): before that they may be another scene's.
    const bool photons_known = std::any_of(stats_.stages.begin(), stats_.stages.end(), [](const StageTime& s) {
        return s.name == "photon pass" || s.name == "photon shooting";
    });
    if (!photons_known) {
        stats_.caustic_lights.clear();
        stats_.caustic_photons = stats_.caustic_map_bytes = 0;
        stats_.gi_lights.clear();
        stats_.gi_photons = stats_.gi_map_bytes = 0;
    }
    for (const StageTime& s : stats_.stages) {
        if (s.cached || is_pass(s.name) || s.name == "progressive passes") continue;
        auto it = std::find_if(computed_stages_.begin(), computed_stages_.end(),
                               [&](const StageTime& c) { return c.name == s.name; });
        if (it == computed_stages_.end()) computed_stages_.push_back(s);
        else *it = s;
    }
}

void PreviewDriver::collect() {
    collected_ = true;
    try {
        session_.wait();  // the worker has stopped: this only joins it, and rethrows its error
    } catch (const std::exception& e) {
        error_ = e.what();
    }
    take_progress();
    poll_stats();
    // Passes that ran to their end; when the render was cancelled, its last pass was cut short.
    std::vector<const StageTime*> passes;
    for (const StageTime& s : stats_.stages)
        if (is_pass(s.name)) passes.push_back(&s);
    if (progress_.cancelled && !passes.empty()) passes.pop_back();
    for (const StageTime* s : passes) record_pass(s->name, s->seconds);
    if (progress_.finished && !stats_forgotten_) refresh_maps();
}

void PreviewDriver::refresh_maps() {
    maps_refreshed_ = true;
    std::vector<LightProjectionMap> maps = session_.projection_maps();
    if (same_projection_maps(maps, maps_)) return;
    maps_ = std::move(maps);
    ++maps_version_;
}

void PreviewDriver::restart() {
    const double t0 = now_seconds();
    job_ = std::move(*pending_);
    pending_.reset();
    paused_ = resume_due_ = false;  // a new job is rendered even when the old one was paused
    new_rules_.reset();             // the job carries its rules
    std::optional<SessionProgress> restored;
    try {
        // The stopped render's last tiles are still the newest: copy them now. From start() on,
        // every tile published belongs to the new render.
        fetch();
        session_.set_coarse_preview(settings_.coarse_preview, settings_.preview_block);
        restored = restore_kept_accumulation();
        std::optional<AccumulationState> saved = std::exchange(pending_saved_, std::nullopt);
        if (!restored) {
            keep_accumulation();
            session_.set_job(job_);  // the worker has stopped: joining it is immediate
            if (!saved || !start_saved_accumulation(std::move(*saved))) session_.start();
        }
    } catch (const std::exception& e) {
        error_ = e.what();
        return;
    }
    accumulation_ = restored ? *restored : SessionProgress{};
    maps_refreshed_ = false;
    stats_forgotten_ = false;
    started_ = true;
    collected_ = false;
    cancel_sent_ = false;
    started_at_ = now_seconds();
    take_progress();
    generation_ = progress_.generation;
    ++restarts_;
    last_restart_ = started_at_ - t0;
    longest_restart_ = std::max(longest_restart_, last_restart_);
}

void PreviewDriver::continue_accumulation() {
    resume_due_ = false;
    fetch();  // the stopped render's last tiles, as restart() does
    if (!session_.resume()) {  // not an accumulation, or paused before its first pass
        pending_ = job_;
        restart();
        return;
    }
    collected_ = false;
    cancel_sent_ = false;
    started_at_ = now_seconds();
    take_progress();
    generation_ = progress_.generation;
}

void PreviewDriver::apply_stop_rules() {
    const StopRules rules = *new_rules_;
    new_rules_.reset();
    rules.apply(job_.options);
    session_.set_stop_rules(rules.passes, rules.time_limit, rules.target_error);  // the worker has stopped
    // The accumulation goes on under the new rules, unless paused (then when resumed).
    // A render its old rules had ended continues too: the new ones may allow more passes.
    if (!paused_ && !pending_ && started_ && (progress_.cancelled || progress_.finished)) continue_accumulation();
}

void PreviewDriver::apply_region() {
    new_region_ = false;
    session_.set_region(region_);  // the worker has stopped: nothing to wait for
}

void PreviewDriver::fetch() {
    previous_seen_ = seen_;
    const int width = image_.width, height = image_.height;
    session_.fetch_tiles(image_, seen_);
    if (image_.width != width || image_.height != height) {  // a new image: earlier copies are gone
        size_changed_ = true;
        changed_.clear();
        changed_generations_.clear();
    }
    if (previous_seen_.size() != seen_.size()) previous_seen_.assign(seen_.size(), 0);
    for (std::size_t i = 0; i < seen_.size(); ++i)
        if (seen_[i] != previous_seen_[i]) {
            changed_.push_back(i);
            changed_generations_.push_back(generation_);
        }
}

std::string stop_reason(const std::string& stopped_by) {
    if (stopped_by == "passes") return "the pass limit";
    if (stopped_by == "time") return "the time limit";
    if (stopped_by == "target error") return "the target error";
    return stopped_by;
}

std::string running_stage(const SessionProgress& progress) {
    if (progress.stage == "progressive passes") return "refining";
    if (progress.stage == "shooting photons" && progress.showing_direct_light) return "direct light; shooting photons";
    return progress.stage.empty() ? "starting" : progress.stage;
}

double render_fraction(const SessionProgress& progress) {
    auto share = [](double done, double total) { return total > 0.0 ? std::min(1.0, done / total) : 0.0; };
    if (progress.running && progress.stage == "shooting photons")  // 0 until the stage knows its total
        return share(static_cast<double>(progress.photons_done), static_cast<double>(progress.photons_total));
    return share(static_cast<double>(progress.tiles_done), static_cast<double>(progress.tiles_total));
}

bool same_projection_maps(const std::vector<LightProjectionMap>& a, const std::vector<LightProjectionMap>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const ProjectionMap& ma = a[i].map;
        const ProjectionMap& mb = b[i].map;
        if (a[i].light_index != b[i].light_index || a[i].light_position != b[i].light_position) return false;
        if (ma.rows() != mb.rows() || ma.columns() != mb.columns()) return false;
        for (int r = 0; r < ma.rows(); ++r)
            for (int c = 0; c < ma.columns(); ++c)
                if (ma.cell(r, c) != mb.cell(r, c)) return false;
    }
    return true;
}

}  // namespace caustica::ui
