// The progressive integrator's render loop: passes of fresh photons gathered with a shrinking
// radius and one new sample per pixel, accumulated until a stopping rule (--passes, --time,
// --target-error) or a cancel; docs/CAUSTICS.md, "Progressive photon mapping". The session runs it
// (RenderHost) and keeps it between renders, so that resume() continues the accumulation.
#pragma once

#include "core/integrators/integrator.h"
#include "core/integrators/progressive_accumulator.h"
#include "core/photons/photon_grid.h"
#include "core/render/render_host.h"
#include "core/render/tile_renderer.h"

#include <glm/vec3.hpp>

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <vector>

namespace caustica {

class ProgressiveIntegrator;

class ProgressiveRender final : public RenderLoop {
public:
    /// Whether the buffers hold passes of the job last rendered (resume() may continue them).
    bool resumable() const override { return state_.valid; }
    /// Forgets the accumulation (another job, or a fresh start), and any snapshot of it.
    void invalidate() override;

    /// Renders passes until a stopping rule or a cancel, continuing the accumulation when it is
    /// resumable. `setup` holds everything but the pass's photon map and radii; `context` the
    /// camera and the base seed.
    void run(RenderHost& host, const ShadingSetup& setup, const TileContext& context) override;

    const ProgressiveAccumulator& accumulator() const { return accumulator_; }

    /// The accumulation as a saved state (docs/OUTPUT.md, "Resuming an accumulation").
    bool save_state(AccumulationState& out) const override;
    /// Takes up a saved accumulation: the next run continues it, its image shown first.
    bool restore_state(AccumulationState&& state) override;
    void request_snapshot() override;
    bool take_snapshot(AccumulationState& out) override;
    /// --layers: each layer's mean over the passes, when every pass of the accumulation rendered them.
    std::vector<LayerImage> layer_images() const override;

private:
    // Kept across renders, so that resume() continues the accumulation.
    struct State {
        bool valid = false;       // the buffers hold passes of the current job
        int next_pass = 0;        // 0-based index of the next pass (of the next round, with ranks)
        int scale_pass = 0;       // the pass scale2 is for
        double scale2 = 1.0;      // (r_i / r_1)^2 of pass scale_pass (+ 1 = i)
        double first_radius = 0.0, radius = 0.0;  // mean radius of the first and the last pass
        double typical_radius = 0.0;  // the first radius of a typical gather (the grid's cells)
        std::uint64_t seed = 0;   // base of the photon and pixel streams
        long long photons_emitted = 0;
        double seconds = 0.0;     // rendering time over every start and resume
        ErrorEstimate error;
        RenderRegion region;      // the pixels the passes go to and the error is estimated over
        std::vector<float> radius_factors;  // per pixel, the multiplier of r^2 (empty: all 1)
        std::vector<std::int64_t> adapted_sums;  // the sums at the last update (rank 0's, with ranks)
    };

    /// Walks the radius sequence (state_.scale2) on to pass `pass`.
    void walk_radius_sequence(int pass, double alpha);
    /// --auto-radius: before pass `pass`, scales the radius sequence from there on so that the
    /// blur and the noise of `e`, the estimate of every rank's sums, balance.
    void balance_radii(const ErrorEstimate& e, int pass, double alpha);
    /// Updates the radius factors from every rank's sums (a collective with ranks).
    void adapt_radii(Cluster* cluster, const std::atomic<bool>& cancel);

    /// A copy of the accumulator with every rank's sums added, on rank 0 (a collective).
    ProgressiveAccumulator summed_on_rank0(Cluster& cluster, const std::atomic<bool>& cancel) const;
    /// The estimate from every rank's sums (a collective).
    ErrorEstimate combined_error(Cluster& cluster, const std::atomic<bool>& cancel);

    /// The saved form of the accumulation, `seconds` of rendering so far.
    AccumulationState saved(double seconds) const;
    /// Makes the snapshot asked for, if one was (between whole passes, alone).
    void snapshot_if_asked(double seconds);

    ProgressiveAccumulator accumulator_;
    State state_;
    bool restored_ = false;  // state_ came from a saved state: its image is not on screen yet
    std::atomic<bool> snapshot_wanted_{false};
    std::mutex snapshot_mutex_;  // guards snapshot_
    std::optional<AccumulationState> snapshot_;
    PhotonGrid grid_;  // the pass's photons (its buffers reused pass after pass)
    std::vector<Photon> spare_photons_;  // the last pass's photon buffer, for the next to fill
    /// --guided-emission: per light the weights of its projection map's cells, learnt from the
    /// first pass for this camera (empty: plain emission, or not learnt yet).
    std::vector<std::vector<float>> emission_weights_;
    // --layers: per written layer, per pixel, the sum of its samples; empty unless every pass of
    // the accumulation added to them.
    std::vector<std::vector<glm::dvec3>> layer_sums_;
};

/// --layers over an accumulation: a pass integrator keeping one layer, and the sums its samples go to.
struct AccumulatedLayer {
    const ProgressiveIntegrator* integrator = nullptr;
    std::vector<glm::dvec3>* sums = nullptr;
};

/// One progressive pass (0-based `pass`) over a tile: a sample per pixel, deterministic per (pixel,
/// pass), traced 8 pixels to a packet, added to the accumulator with its photon probes; the
/// pixel's mean goes to `out`. `radius_factors` (per pixel, or null: all 1) multiply the r^2 of
/// each pixel's gathers. `layers` (or null) trace the same rays with the same random streams and
/// add their samples to their sums (their rays are not counted). Once context.cancel is set the tile stops, the packet traced then adding
/// nothing: the pixels it reached keep this pass's sample, the others do not have it.
void render_accumulation_tile(const ProgressiveIntegrator& integrator, const TileContext& context, const Tile& tile,
                              int pass, const float* radius_factors, ProgressiveAccumulator& accumulator, Image& out,
                              RayCounters& counters, const std::vector<AccumulatedLayer>* layers = nullptr);

}  // namespace caustica
