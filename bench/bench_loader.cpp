// What running a scene script costs, in this process and in the loader's child process (the
// sandbox's price: fork, the script, the scene sent back as bytes and checked).
//   build/bench_loader --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "core/lua/scene_loader.h"

#include <benchmark/benchmark.h>

#include <string>

namespace caustica {
namespace {

void BM_Load(benchmark::State& state, const std::string& scene, bool isolated) {
    LoadSettings settings;
    std::size_t nodes = 0;
    for (auto _ : state) {
        const SceneScript script =
            isolated ? load_scene_script(scene, settings) : load_scene_script_in_process(scene, settings);
        nodes = script.renders.at(0).scene->nodes.size();
        benchmark::DoNotOptimize(nodes);
    }
    state.counters["nodes"] = static_cast<double>(nodes);
}

const std::string default_scene = CAUSTICA_SOURCE_DIR "/scenes/default.lua";
const std::string textures_scene = CAUSTICA_SOURCE_DIR "/scenes/textures.lua";

BENCHMARK_CAPTURE(BM_Load, default_in_process, default_scene, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Load, default_isolated, default_scene, true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Load, textures_in_process, textures_scene, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Load, textures_isolated, textures_scene, true)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace caustica

BENCHMARK_MAIN();
