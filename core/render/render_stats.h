// Counters and stage times of a render, for -S and -t.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace caustica {

/// Ray counts by kind; accumulated per thread and summed.
struct RayCounters {
    std::uint64_t primary = 0;
    std::uint64_t shadow = 0;
    std::uint64_t reflected = 0;
    std::uint64_t refracted = 0;
    std::uint64_t samples = 0;           ///< camera samples taken
    std::uint64_t supersampled_pixels = 0;
    std::uint64_t gathers = 0;           ///< caustic radiance estimates
    double gather_seconds = 0.0;         ///< time spent in them (summed over threads; see GatherTimer)
    // Progressive photon mapping's probes, read per camera ray by the pass loop: the gathered
    // photon radiance kd E (mean of the channels) at the pass radius r and at r/sqrt 2 (their
    // difference estimates the radius bias), and the logarithms of the radii gathered with (their
    // geometric mean is the pass's radius, for reports).
    double photon_value = 0.0, photon_value_inner = 0.0;
    double radius_log_sum = 0.0;
    std::uint64_t radius_samples = 0;

    RayCounters& operator+=(const RayCounters& o) {
        primary += o.primary, shadow += o.shadow, reflected += o.reflected, refracted += o.refracted;
        samples += o.samples, supersampled_pixels += o.supersampled_pixels;
        gathers += o.gathers, gather_seconds += o.gather_seconds;
        photon_value += o.photon_value, photon_value_inner += o.photon_value_inner;
        radius_log_sum += o.radius_log_sum, radius_samples += o.radius_samples;
        return *this;
    }
    std::uint64_t total_rays() const { return primary + shadow + reflected + refracted; }
};

/// Times one gather in every 32 (reading the clock costs as much as a small gather) and counts it
/// 32 times: the statistics' share of time in radiance estimates, without its own cost.
class GatherTimer {
public:
    explicit GatherTimer(RayCounters& counters)
        : counters_(counters), timed_((counters.gathers & 31) == 0) {
        if (timed_) start_ = std::chrono::steady_clock::now();
    }
    ~GatherTimer() {
        if (timed_) counters_.gather_seconds += 32.0 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        ++counters_.gathers;
    }
    GatherTimer(const GatherTimer&) = delete;
    GatherTimer& operator=(const GatherTimer&) = delete;

private:
    RayCounters& counters_;
    bool timed_;
    std::chrono::steady_clock::time_point start_;
};

/// One timed stage ("scene build", "first pass", ...).
struct StageTime {
    std::string name;
    double seconds = 0.0;
    bool cached = false;  ///< reused from a previous render, not recomputed
};

/// Counts of what a build produced, for -S.
struct SceneBuildInfo {
    std::size_t analytic_primitives = 0;
    std::size_t mesh_instances = 0;
    std::size_t unique_meshes = 0;
    std::size_t triangles_stored = 0;     ///< triangles held once per mesh file
    std::size_t triangles_instanced = 0;  ///< triangles as seen in the world
    std::size_t csg_objects = 0;
    std::size_t csg_leaves = 0;           ///< primitives inside CSG objects
    double estimated_bytes = 0.0;         ///< what it was estimated to cost, textures included (scene_memory.h)
};

/// The caustic photon pass of one light, for -S.
struct LightCausticStats {
    long long candidates = 0, traced = 0, stored = 0;
    bool projection_map_used = false;
    double occupied_fraction = 1.0;
};

/// Everything -S and -t report.
struct RenderStats {
    RayCounters rays;
    std::vector<StageTime> stages;
    SceneBuildInfo scene;                ///< what the last scene build produced
    int threads = 0;
    double total_seconds = 0.0;
    std::vector<LightCausticStats> caustic_lights;
    std::size_t caustic_photons = 0, caustic_map_bytes = 0;
    std::vector<LightCausticStats> gi_lights;  ///< classic --gi: the GI pass of each light
    std::size_t gi_photons = 0, gi_map_bytes = 0;
    std::string integrator;                    ///< "classic" or "progressive"
    /// Progressive passes (docs/CAUSTICS.md, "Progressive photon mapping"); passes = 0 when the
    /// render did not accumulate.
    struct Accumulation {
        int passes = 0;
        double first_radius = 0.0, radius = 0.0;  ///< geometric mean gather radius of the first and the last pass
        long long photons_emitted = 0;            ///< directions over every pass
        double error = -1.0, noise = 0.0, bias = 0.0;  ///< estimated relative error (< 0: unknown)
        std::size_t bytes = 0;                    ///< the accumulation buffers
        std::string stopped_by;                   ///< "passes", "time", "target error", "cancelled"
    } accumulation;
};

}  // namespace caustica
