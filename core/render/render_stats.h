// Counters and stage times of a render, for -S and -t.
#pragma once

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
    double gather_seconds = 0.0;         ///< time spent in them (summed over threads)

    RayCounters& operator+=(const RayCounters& o) {
        primary += o.primary, shadow += o.shadow, reflected += o.reflected, refracted += o.refracted;
        samples += o.samples, supersampled_pixels += o.supersampled_pixels;
        gathers += o.gathers, gather_seconds += o.gather_seconds;
        return *this;
    }
    std::uint64_t total_rays() const { return primary + shadow + reflected + refracted; }
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
};

}  // namespace caustica
