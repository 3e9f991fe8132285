// Rendering throughput: primary-ray shading against Embree's raw packet rate on the same rays,
// and whole renders of macho-cows.lua at 512 x 512 on 1 and 2 threads (scenes of ../shared/cs488:
// without it, nothing runs and the program says so).
//   build/bench_render --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "bench/primary_rays.h"
#include "core/scene/camera.h"
#include "core/integrators/progressive.h"
#include "core/lua/scene_loader.h"
#include "core/geometry/render_scene.h"
#include "core/render/render_session.h"
#include "core/scene/scene_flatten.h"
#include "core/render/tile_renderer.h"

#include <benchmark/benchmark.h>
#include <xmmintrin.h>
#include <pmmintrin.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

namespace {

using namespace caustica;

constexpr int bench_size = 512;

/// A course scene loaded once, with --a4, at the benchmark resolution.
const RenderJob& course_job(const std::string& name) {
    static std::map<std::string, RenderJob> jobs;
    auto it = jobs.find(name);
    if (it != jobs.end()) return it->second;
    LoadSettings settings;
    settings.base_options.a4 = true;
    RenderJob job = load_scene_script(std::string(CAUSTICA_CS488_DIR) + "/" + name, settings).renders.at(0);
    job.options.a4 = true;
    job.options.silent = true;
    job.options.reproducible = true;
    job.width = job.height = bench_size;
    return jobs.emplace(name, job).first->second;
}

/// Everything the single-thread shading benchmarks share for one scene.
struct ShadingFixture {
    std::unique_ptr<RenderScene> scene;
    ShadingSetup setup;
    std::unique_ptr<Camera> camera;
    std::vector<Tile> tiles;

    explicit ShadingFixture(const RenderJob& job) {
        _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
        _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
        scene = std::make_unique<RenderScene>(*job.scene, flatten_scene(*job.scene, job.root, true));
        setup.scene = scene.get();
        for (int index : job.lights) {
            const LightDesc& d = job.scene->lights[index];
            setup.lights.push_back({glm::vec3(d.position), glm::vec3(d.colour), glm::vec3(d.falloff), 0.0f});
        }
        setup.ambient = glm::vec3(job.ambient);
        camera = std::make_unique<Camera>(job.camera, job.width, job.height);
        tiles = make_tiles(job.width, job.height, tile_size);
    }
};

/// Full Phong shading of one primary sample per pixel (with shadow rays), one thread.
void BM_PrimaryShading(benchmark::State& state, const std::string& scene_name) {
    const RenderJob& job = course_job(scene_name);
    ShadingFixture f(job);
    const ProgressiveIntegrator integrator(f.setup);
    TileContext context;
    context.integrator = &integrator;
    context.camera = f.camera.get();
    Image image(job.width, job.height);
    RayCounters counters;
    for (auto _ : state) {
        for (const Tile& tile : f.tiles) render_first_pass_tile(context, tile, image, counters);
        benchmark::DoNotOptimize(image.pixels.data());
    }
    state.SetItemsProcessed(state.iterations() * job.width * job.height);
    state.counters["rays_per_pixel"] = double(counters.total_rays()) / double(counters.samples);
}

/// Embree's rtcIntersect8 on exactly the same primary rays, nothing else, one thread.
void BM_EmbreeIntersect8Raw(benchmark::State& state, const std::string& scene_name) {
    const RenderJob& job = course_job(scene_name);
    ShadingFixture f(job);
    RTCScene scene = f.scene->embree_scene();
    RayQueryContext context;  // its user-geometry callbacks read one
    for (auto _ : state) {
        unsigned hits = 0;
        for (const Tile& tile : f.tiles)
            for (int y = tile.y0; y < tile.y1; ++y)
                for (int x = tile.x0; x < tile.x1; x += 8)
                    hits += bench::trace_primary_packet(scene, context, *f.camera, x, y, tile.x1);
        benchmark::DoNotOptimize(hits);
    }
    state.SetItemsProcessed(state.iterations() * job.width * job.height);
}

/// The same primary rays one at a time through rtcIntersect1: what the packet path saves.
void BM_EmbreeIntersect1Raw(benchmark::State& state, const std::string& scene_name) {
    const RenderJob& job = course_job(scene_name);
    ShadingFixture f(job);
    RTCScene scene = f.scene->embree_scene();
    RayQueryContext context;  // its user-geometry callbacks read one
    for (auto _ : state) {
        unsigned hits = 0;
        for (const Tile& tile : f.tiles)
            for (int y = tile.y0; y < tile.y1; ++y)
                for (int x = tile.x0; x < tile.x1; ++x) hits += bench::trace_primary_ray(scene, context, *f.camera, x, y);
        benchmark::DoNotOptimize(hits);
    }
    state.SetItemsProcessed(state.iterations() * job.width * job.height);
}

/// A whole render (both passes) through the render session, at `threads` threads.
void BM_WholeRender(benchmark::State& state, const std::string& scene_name) {
    RenderJob job = course_job(scene_name);
    job.options.threads = static_cast<int>(state.range(0));
    RenderSession session;
    session.set_job(job);
    session.prepare();  // the BVH is built once; each iteration renders
    for (auto _ : state) {
        session.start();
        session.wait();
    }
    state.SetItemsProcessed(state.iterations() * job.width * job.height);
}

BENCHMARK_CAPTURE(BM_PrimaryShading, nonhier, std::string("nonhier.lua"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeIntersect8Raw, nonhier, std::string("nonhier.lua"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeIntersect1Raw, nonhier, std::string("nonhier.lua"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeIntersect1Raw, macho_cows, std::string("macho-cows.lua"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PrimaryShading, macho_cows, std::string("macho-cows.lua"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_EmbreeIntersect8Raw, macho_cows, std::string("macho-cows.lua"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_WholeRender, macho_cows, std::string("macho-cows.lua"))
    ->Arg(1)
    ->Arg(2)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
    // The scenes are those of ../shared/cs488: a clone on its own skips these benchmarks.
    if (!std::filesystem::is_directory(CAUSTICA_CS488_DIR)) {
        std::printf("bench_render: skipped: ../shared/cs488 not found: %s is missing; the course scenes "
                    "(the shared folder beside the repository) are needed for these benchmarks\n",
                    CAUSTICA_CS488_DIR);
        return 0;
    }
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
