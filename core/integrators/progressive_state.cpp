// The progressive render loop's state between renders: forgetting it, saving it to a file and
// restoring it (docs/OUTPUT.md, "Resuming an accumulation"), the layers' images, and the snapshots
// the preview takes while passes run. The loop itself is in progressive_render.cpp.
#include "core/integrators/progressive_render.h"

#include <cstddef>
#include <mutex>
#include <utility>
#include <vector>

namespace caustica {

void ProgressiveRender::invalidate() {
    state_.valid = false;
    std::vector<Photon>().swap(spare_photons_);
    emission_weights_.clear();
    layer_sums_.clear();
    snapshot_wanted_ = false;
    std::lock_guard lock(snapshot_mutex_);
    snapshot_.reset();
}

AccumulationState ProgressiveRender::saved(double seconds) const {
    AccumulationState s;
    s.key.width = accumulator_.width();
    s.key.height = accumulator_.height();
    s.next_pass = state_.next_pass;
    s.scale_pass = state_.scale_pass;
    s.scale2 = state_.scale2;
    s.first_radius = state_.first_radius;
    s.radius = state_.radius;
    s.typical_radius = state_.typical_radius;
    s.seed = state_.seed;
    s.photons_emitted = state_.photons_emitted;
    s.seconds = seconds;
    s.sums = accumulator_.sums();
    s.radius_factors = state_.radius_factors;
    s.adapted_sums = state_.adapted_sums;
    return s;
}

bool ProgressiveRender::save_state(AccumulationState& out) const {
    if (!state_.valid) return false;
    out = saved(state_.seconds);
    return true;
}

bool ProgressiveRender::restore_state(AccumulationState&& s) {
    const std::size_t pixels = static_cast<std::size_t>(std::max(0, s.key.width)) * static_cast<std::size_t>(std::max(0, s.key.height));
    const bool fits = pixels > 0 && s.sums.size() == pixels * ProgressiveAccumulator::sums_per_pixel &&
                      (s.radius_factors.empty() || s.radius_factors.size() == pixels) &&
                      (s.adapted_sums.empty() || s.adapted_sums.size() == pixels * ProgressiveAccumulator::snapshot_slots);
    invalidate();
    if (!fits) return false;
    accumulator_.adopt(s.key.width, s.key.height, std::move(s.sums));
    state_ = State{};
    state_.valid = true;
    state_.next_pass = s.next_pass;
    state_.scale_pass = s.scale_pass;
    state_.scale2 = s.scale2;
    state_.first_radius = s.first_radius;
    state_.radius = s.radius;
    // The grid's cell size is measured again (a function of the scene and camera alone, so the same
    // bits), never taken from a file that may not be ours.
    state_.typical_radius = 0.0;
    state_.seed = s.seed;
    state_.photons_emitted = s.photons_emitted;
    state_.seconds = s.seconds;
    state_.error = accumulator_.estimate_error();
    state_.radius_factors = std::move(s.radius_factors);
    state_.adapted_sums = std::move(s.adapted_sums);
    restored_ = true;
    return true;
}

std::vector<LayerImage> ProgressiveRender::layer_images() const {
    std::vector<LayerImage> out;
    if (!state_.valid || layer_sums_.size() != std::size(written_layers)) return out;
    const int width = accumulator_.width(), height = accumulator_.height();
    for (std::size_t l = 0; l < layer_sums_.size(); ++l) {
        LayerImage layer{written_layers[l], Image(width, height)};
        for (std::size_t i = 0; i < layer.image.pixels.size(); ++i)
            if (const std::uint32_t n = accumulator_.samples(i); n > 0)
                layer.image.pixels[i] = glm::vec3(layer_sums_[l][i] / static_cast<double>(n));
        out.push_back(std::move(layer));
    }
    return out;
}

void ProgressiveRender::request_snapshot() {
    // A snapshot made for an earlier request nobody took is stale: the next one is made afresh.
    std::lock_guard lock(snapshot_mutex_);
    snapshot_.reset();
    snapshot_wanted_ = true;
}

bool ProgressiveRender::take_snapshot(AccumulationState& out) {
    std::lock_guard lock(snapshot_mutex_);
    if (!snapshot_) return false;
    out = std::move(*snapshot_);
    snapshot_.reset();
    return true;
}

void ProgressiveRender::snapshot_if_asked(double seconds) {
    if (!snapshot_wanted_.exchange(false)) return;
    AccumulationState copy = saved(seconds);  // outside the lock: the front end never waits for the copy
    std::lock_guard lock(snapshot_mutex_);
    snapshot_ = std::move(copy);
}

}  // namespace caustica
