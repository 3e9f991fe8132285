// The fixed-radius gathers of progressive photon mapping: the hashed photon grid (built each pass)
// against the k-d tree (for_each_within) on the same photons, queries and radii, and the two
// builds. Photons lie on a floor as a pass's caustic map does: a focus, a cardioid and a thin
// background; queries cover the caustic region on a 256 x 256 grid in tile (Morton) order, the
// order a tile renderer asks in. Radii from a sub-pixel footprint to the single pass's k-nearest
// radius.
//   build/bench_photon_grid --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "core/photons/photon_grid.h"
#include "core/photons/photon_map.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>

namespace {

using caustica::Photon;
using caustica::PhotonGrid;
using caustica::PhotonKdTree;

std::vector<Photon> caustic_photons(std::size_t n) {
    std::mt19937 rng(42);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Photon> p(n);
    for (Photon& photon : p) {
        const float r = u(rng);
        if (r < 0.5f) {  // the focused spot under a glass sphere
            photon.position = {0.6f + 0.04f * gauss(rng), 0.0f, 0.05f * gauss(rng)};
        } else if (r < 0.9f) {  // a cardioid inside a ring, with some spread
            const float t = 6.2831853f * u(rng);
            const float rho = 0.25f * (1.0f + std::cos(t));
            photon.position = {-0.8f + rho * std::cos(t) + 0.01f * gauss(rng), 0.0f, rho * std::sin(t) + 0.01f * gauss(rng)};
        } else {  // a thin background over the floor
            photon.position = {4.0f * u(rng) - 2.0f, 0.0f, 4.0f * u(rng) - 2.0f};
        }
        photon.power = glm::vec3(1e-6f);
        photon.direction = glm::normalize(glm::vec3(gauss(rng), -3.0f, gauss(rng)));
    }
    return p;
}

const std::vector<Photon>& photons(std::size_t n) {
    static std::map<std::size_t, std::vector<Photon>> cache;
    auto it = cache.find(n);
    if (it == cache.end()) it = cache.emplace(n, caustic_photons(n)).first;
    return it->second;
}

std::uint32_t morton2(std::uint32_t x, std::uint32_t y) {
    auto spread = [](std::uint32_t v) {
        v &= 0xffff;
        v = (v | (v << 8)) & 0x00ff00ff;
        v = (v | (v << 4)) & 0x0f0f0f0f;
        v = (v | (v << 2)) & 0x33333333;
        v = (v | (v << 1)) & 0x55555555;
        return v;
    };
    return spread(x) | (spread(y) << 1);
}

const std::vector<glm::vec3>& queries() {
    static std::vector<glm::vec3> tile;
    if (tile.empty()) {
        constexpr std::uint32_t size = 256;
        std::vector<std::pair<std::uint32_t, glm::vec3>> keyed;
        for (std::uint32_t y = 0; y < size; ++y)
            for (std::uint32_t x = 0; x < size; ++x)
                keyed.push_back({morton2(x, y), {-1.2f + 2.2f * x / size, 0.0f, -0.6f + 1.2f * y / size}});
        std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (const auto& k : keyed) tile.push_back(k.second);
    }
    return tile;
}

const caustica::PhotonMap& map_of(std::size_t n) {
    static std::map<std::size_t, std::unique_ptr<caustica::PhotonMap>> cache;
    auto& slot = cache[n];
    if (!slot) slot = std::make_unique<caustica::PhotonMap>(photons(n));
    return *slot;
}

void gather_tree(benchmark::State& state, std::size_t n, float radius) {
    const caustica::PhotonMap& map = map_of(n);
    const glm::vec3 normal(0, 1, 0);
    double sum = 0.0;
    for (auto _ : state)
        for (const glm::vec3& p : queries()) sum += map.disc_estimate(p, normal, radius, nullptr).x;
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(queries().size()));
}

void gather_grid(benchmark::State& state, std::size_t n, float radius, float cell_factor) {
    PhotonGrid grid;
    grid.build(photons(n), cell_factor * radius);
    const glm::vec3 normal(0, 1, 0);
    double sum = 0.0;
    std::uint64_t found = 0;
    for (auto _ : state)
        for (const glm::vec3& p : queries()) {
            const PhotonGrid::Gather g = grid.gather(p, normal, radius);
            sum += g.sum.x;
            found += g.count;
        }
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(queries().size()));
    state.counters["found_per_query"] = double(found) / double(state.iterations() * queries().size());
}

void build_tree(benchmark::State& state, std::size_t n) {
    for (auto _ : state) {
        caustica::PhotonMap map(photons(n));
        benchmark::DoNotOptimize(map.size());
    }
}

void build_grid(benchmark::State& state, std::size_t n) {
    PhotonGrid grid;  // reused, as a pass reuses it
    for (auto _ : state) {
        grid.build(photons(n), 0.01f);
        benchmark::DoNotOptimize(grid.size());
    }
}

const int registered = [] {
    for (std::size_t n : {std::size_t(1) << 18, std::size_t(1) << 20}) {
        const std::string size = n == (std::size_t(1) << 18) ? "256K" : "1M";
        benchmark::RegisterBenchmark(("build/tree/photons:" + size).c_str(), build_tree, n)->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("build/grid/photons:" + size).c_str(), build_grid, n)->Unit(benchmark::kMillisecond);
        for (float radius : {0.003f, 0.01f, 0.03f}) {
            const std::string suffix = "/photons:" + size + "/radius:" + std::to_string(radius).substr(0, 5);
            benchmark::RegisterBenchmark(("gather/tree" + suffix).c_str(), gather_tree, n, radius)->Unit(benchmark::kMillisecond);
            for (float cell : {2.0f, 3.0f, 4.0f})
                benchmark::RegisterBenchmark(("gather/grid" + suffix + "/cell:" + std::to_string(int(cell)) + "r").c_str(),
                                             gather_grid, n, radius, cell)
                    ->Unit(benchmark::kMillisecond);
        }
    }
    return 0;
}();

}  // namespace

BENCHMARK_MAIN();
