// The photon pass: photons per second on 1 and 2 threads, and projection maps on/off/auto on a
// dense scene (a closed room: every photon meets something), a sparse one (a few objects in open
// space: photons that miss escape at once) and an enclosed one (the light inside a glass shell: the
// map cannot pay), after the original's tables (3.2x and 0.7x). photon_pass/default_scene: the demo
// scene scenes/default.lua (the throughput target of docs/PERFORMANCE.md: traced photons per second
// on 2 threads, the "traced_per_s" counter), 10^7 directions as its --quality preview shoots.
//   build/bench_photons --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "core/lua/scene_loader.h"
#include "core/photons/caustic_stage.h"
#include "core/photons/photon_tracer.h"
#include "core/scene/scene_flatten.h"
#include "tests/test_support.h"

#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <memory>
#include <string>

namespace {

using namespace caustica;
using caustica::testing::JobBuilder;

int glass_material(JobBuilder& b) {
    MaterialDesc glass;
    glass.ks = glm::dvec3(0.9);
    glass.refractive_index = 1.5;
    b.scene->materials.push_back(glass);
    return static_cast<int>(b.scene->materials.size()) - 1;
}

/// Three specular spheres under a light inside a closed diffuse room: about 10% of the sphere.
RenderJob dense_scene() {
    JobBuilder b(8, 8);
    const int wall = b.material({0.7, 0.7, 0.7});
    const int room = b.add(NodeKind::group, -1);
    for (int axis = 0; axis < 3; ++axis)
        for (int side = -1; side <= 1; side += 2) {
            const int w = b.add(NodeKind::cube, wall, room);
            glm::dvec3 t(0.0), s(4.0);
            t[axis] = 4.0 * side;
            s[axis] = 0.05;
            b.translate(w, t);
            b.scale(w, s);
        }
    const int glass = glass_material(b);
    const int mirror = b.material({0, 0, 0}, glm::dvec3(0.9), 0, true);
    const glm::dvec3 centres[3] = {{-1.2, -1.5, 0}, {1.2, -1.5, 0.4}, {0, -1.5, -1.3}};
    for (int i = 0; i < 3; ++i) {
        const int ball = b.add(NodeKind::sphere, i == 1 ? mirror : glass);
        b.translate(ball, centres[i]);
        b.scale(ball, glm::dvec3(0.9));
    }
    b.light({0, 2, 0}, {1, 1, 1}, {0, 0, 1});
    return b.build();
}

/// A glass sphere and a floor tile in open space: photons that miss them cost one ray each.
RenderJob sparse_scene() {
    JobBuilder b(8, 8);
    const int floor = b.add(NodeKind::cube, b.material({0.7, 0.7, 0.7}));
    b.translate(floor, {0, -2, 0});
    b.scale(floor, {2, 0.05, 2});
    const int ball = b.add(NodeKind::sphere, glass_material(b));
    b.translate(ball, {0, -1, 0});
    b.scale(ball, glm::dvec3(0.5));
    b.light({0, 2, 0}, {1, 1, 1}, {0, 0, 1});
    return b.build();
}

/// A light inside a glass shell inside a room: every direction is occupied, the map cannot pay.
RenderJob enclosed_scene() {
    JobBuilder b(8, 8);
    const int floor = b.add(NodeKind::cube, b.material({0.7, 0.7, 0.7}));
    b.translate(floor, {0, -2, 0});
    b.scale(floor, {4, 0.05, 4});
    const int shell = b.add(NodeKind::sphere, glass_material(b));
    b.translate(shell, {0, 0.5, 0});
    b.light({0, 0.5, 0}, {1, 1, 1}, {0, 0, 1});
    return b.build();
}

struct Fixture {
    RenderJob job;
    std::unique_ptr<RenderScene> scene;
    explicit Fixture(RenderJob j) : job(std::move(j)) {
        scene = std::make_unique<RenderScene>(*job.scene, flatten_scene(*job.scene, job.root, false));
    }
};

const Fixture& fixture(int scene) {
    static const Fixture dense(dense_scene()), sparse(sparse_scene()), enclosed(enclosed_scene());
    if (scene == 3) {
        static const Fixture demo(load_scene_script(std::string(CAUSTICA_SOURCE_DIR) + "/scenes/default.lua").renders.at(0));
        return demo;
    }
    return scene == 0 ? dense : scene == 1 ? sparse : enclosed;
}

void photon_pass(benchmark::State& state, int scene, ProjectionMapMode mode) {
    const Fixture& f = fixture(scene);
    const int threads = static_cast<int>(state.range(0));
    PhotonPassSettings settings;
    settings.photons_per_light = scene == 3 ? 10'000'000 : 1'000'000;
    settings.projection_map = mode;
    tbb::task_arena arena(threads);
    PhotonPassResult result;
    for (auto _ : state) arena.execute([&] { result = shoot_caustic_photons(*f.scene, job_lights(f.job), settings, nullptr); });
    state.SetItemsProcessed(state.iterations() * settings.photons_per_light);
    state.counters["traced"] = static_cast<double>(result.lights[0].traced);
    state.counters["stored"] = static_cast<double>(result.lights[0].stored);
    state.counters["occupied"] = result.lights[0].occupied_fraction;
    state.counters["map_used"] = result.lights[0].projection_map_used;
    // Photons traced (the directions the projection map lets through) per second of wall time.
    state.counters["traced_per_s"] =
        benchmark::Counter(static_cast<double>(result.lights[0].traced) * static_cast<double>(state.iterations()),
                           benchmark::Counter::kIsRate);
}

const int registered = [] {
    const char* scenes[] = {"dense", "sparse", "enclosed"};
    for (int scene = 0; scene < 3; ++scene)
        for (ProjectionMapMode mode : {ProjectionMapMode::on, ProjectionMapMode::off, ProjectionMapMode::automatic}) {
            const std::string name = std::string("photon_pass/") + scenes[scene] + "/map:" +
                                     (mode == ProjectionMapMode::on ? "on" : mode == ProjectionMapMode::off ? "off" : "auto");
            benchmark::RegisterBenchmark(name.c_str(), photon_pass, scene, mode)
                ->Arg(1)
                ->Arg(2)
                ->ArgName("threads")
                ->UseRealTime()
                ->Unit(benchmark::kMillisecond);
        }
    benchmark::RegisterBenchmark("photon_pass/default_scene/map:auto", photon_pass, 3, ProjectionMapMode::automatic)
        ->Arg(1)
        ->Arg(2)
        ->ArgName("threads")
        ->UseRealTime()
        ->Unit(benchmark::kMillisecond);
    return 0;
}();

}  // namespace

BENCHMARK_MAIN();
