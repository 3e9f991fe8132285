// Our photon k-D tree against nanoflann on the same photons and queries (docs/PERFORMANCE.md).
// Photons are clustered on a floor as a real caustic map is: a focused spot, a cardioid and a thin
// background. Queries cover the caustic region on a 256 x 256 grid, in tile (Morton) order or in
// random order. nanoflann gets its best configuration: leaf size 10 and a radius-bounded max-heap
// result set (the same bound and heap our tree uses). The always_k pairs compare the classic
// search (always k photons, pruned at 0.15 once k are held) with nanoflann's unbounded knnSearch.
//   build/bench_photon_knn --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "core/photons/photon_kdtree.h"

#include <benchmark/benchmark.h>
#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>

namespace {

using caustica::Neighbour;
using caustica::PhotonKdTree;

constexpr float max_distance = 0.1f;
constexpr float classic_prune_distance = 0.15f;  // the classic search's prune distance, 0.15 d_u

std::vector<glm::vec3> caustic_photons(std::size_t n) {
    std::mt19937 rng(42);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<glm::vec3> p(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float r = u(rng);
        if (r < 0.5f) {  // the focused spot under a glass sphere
            p[i] = {0.6f + 0.04f * gauss(rng), 0.0f, 0.05f * gauss(rng)};
        } else if (r < 0.9f) {  // a cardioid inside a ring, with some spread
            const float t = 6.2831853f * u(rng);
            const float rho = 0.25f * (1.0f + std::cos(t));
            p[i] = {-0.8f + rho * std::cos(t) + 0.01f * gauss(rng), 0.0f, rho * std::sin(t) + 0.01f * gauss(rng)};
        } else {  // a thin background over the floor
            p[i] = {4.0f * u(rng) - 2.0f, 0.0f, 4.0f * u(rng) - 2.0f};
        }
    }
    return p;
}

const std::vector<glm::vec3>& photons(std::size_t n) {
    static std::map<std::size_t, std::vector<glm::vec3>> cache;
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

/// Query points over the caustic region x in [-1.2, 1], z in [-0.6, 0.6].
const std::vector<glm::vec3>& queries(bool tile_order) {
    static std::vector<glm::vec3> tile, shuffled;
    if (tile.empty()) {
        constexpr std::uint32_t size = 256;
        std::vector<std::pair<std::uint32_t, glm::vec3>> keyed;
        for (std::uint32_t y = 0; y < size; ++y)
            for (std::uint32_t x = 0; x < size; ++x)
                keyed.push_back({morton2(x, y), {-1.2f + 2.2f * x / size, 0.0f, -0.6f + 1.2f * y / size}});
        std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (const auto& k : keyed) tile.push_back(k.second);
        shuffled = tile;
        std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(7));
    }
    return tile_order ? tile : shuffled;
}

const PhotonKdTree& our_tree(std::size_t n) {
    static std::map<std::size_t, std::unique_ptr<PhotonKdTree>> cache;
    auto& slot = cache[n];
    if (!slot) slot = std::make_unique<PhotonKdTree>(photons(n));
    return *slot;
}

struct Cloud {
    const std::vector<glm::vec3>* points;
    std::size_t kdtree_get_point_count() const { return points->size(); }
    float kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*points)[i][static_cast<int>(dim)]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const { return false; }
};

using NanoTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, 3, std::uint32_t>;

struct NanoIndex {
    Cloud cloud;
    NanoTree tree;
    explicit NanoIndex(const std::vector<glm::vec3>* p)
        : cloud{p}, tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10)) {}
};

const NanoIndex& nano_tree(std::size_t n) {
    static std::map<std::size_t, std::unique_ptr<NanoIndex>> cache;
    auto& slot = cache[n];
    if (!slot) slot = std::make_unique<NanoIndex>(&photons(n));
    return *slot;
}

/// nanoflann result set: a max-heap of k entries bounded by the maximum distance from the start.
class BoundedHeapResult {
public:
    BoundedHeapResult(Neighbour* heap, std::uint32_t k, float radius2) : heap_(heap), k_(k), radius2_(radius2) {}
    bool addPoint(float d2, std::uint32_t index) {
        if (d2 >= worstDist()) return true;
        if (count_ < k_) {
            heap_[count_++] = {d2, index};
            std::push_heap(heap_, heap_ + count_);
        } else {
            std::pop_heap(heap_, heap_ + k_);
            heap_[k_ - 1] = {d2, index};
            std::push_heap(heap_, heap_ + k_);
        }
        return true;
    }
    float worstDist() const { return count_ == k_ ? heap_[0].distance2 : radius2_; }
    bool full() const { return count_ == k_; }
    std::uint32_t size() const { return count_; }

private:
    Neighbour* heap_;
    std::uint32_t k_, count_ = 0;
    float radius2_;
};

void knn_caustica(benchmark::State& state, std::size_t n, std::uint32_t k, bool tile_order) {
    const PhotonKdTree& tree = our_tree(n);
    const auto& q = queries(tile_order);
    std::vector<Neighbour> heap(k);
    std::size_t found = 0;
    for (auto _ : state)
        for (const glm::vec3& p : q) found += tree.nearest(p, k, max_distance, heap.data());
    benchmark::DoNotOptimize(found);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(q.size()));
    state.counters["found_per_query"] = double(found) / double(state.iterations() * q.size());
}

void knn_nanoflann(benchmark::State& state, std::size_t n, std::uint32_t k, bool tile_order) {
    const NanoIndex& index = nano_tree(n);
    const auto& q = queries(tile_order);
    std::vector<Neighbour> heap(k);
    std::size_t found = 0;
    for (auto _ : state)
        for (const glm::vec3& p : q) {
            BoundedHeapResult result(heap.data(), k, max_distance * max_distance);
            index.tree.findNeighbors(result, &p.x, nanoflann::SearchParams(0, 0.0f, false));
            found += result.size();
        }
    benchmark::DoNotOptimize(found);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(q.size()));
    state.counters["found_per_query"] = double(found) / double(state.iterations() * q.size());
}

/// The classic search (docs/CAUSTICS.md, "search"): always k photons, pruned at 0.15 once k are
/// held.
void always_k_caustica(benchmark::State& state, std::size_t n, std::uint32_t k, bool tile_order) {
    const PhotonKdTree& tree = our_tree(n);
    const auto& q = queries(tile_order);
    std::vector<Neighbour> heap(k);
    std::size_t found = 0;
    for (auto _ : state)
        for (const glm::vec3& p : q) found += tree.nearest_always(p, k, classic_prune_distance, heap.data());
    benchmark::DoNotOptimize(found);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(q.size()));
    state.counters["found_per_query"] = double(found) / double(state.iterations() * q.size());
}

/// nanoflann's own k-nearest search (unbounded: always k), the closest standard counterpart.
void always_k_nanoflann(benchmark::State& state, std::size_t n, std::uint32_t k, bool tile_order) {
    const NanoIndex& index = nano_tree(n);
    const auto& q = queries(tile_order);
    std::vector<std::uint32_t> indices(k);
    std::vector<float> distances(k);
    std::size_t found = 0;
    for (auto _ : state)
        for (const glm::vec3& p : q) found += index.tree.knnSearch(&p.x, k, indices.data(), distances.data());
    benchmark::DoNotOptimize(found);
    state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(q.size()));
    state.counters["found_per_query"] = double(found) / double(state.iterations() * q.size());
}

void build_caustica(benchmark::State& state, std::size_t n) {
    for (auto _ : state) {
        PhotonKdTree tree(photons(n));
        benchmark::DoNotOptimize(tree.size());
    }
}

void build_nanoflann(benchmark::State& state, std::size_t n) {
    for (auto _ : state) {
        NanoIndex index(&photons(n));
        benchmark::DoNotOptimize(&index);
    }
}

const int registered = [] {
    for (std::size_t n : {std::size_t(1) << 20, std::size_t(4) << 20}) {
        const std::string size = n == (std::size_t(1) << 20) ? "1M" : "4M";
        benchmark::RegisterBenchmark(("build/caustica/photons:" + size).c_str(), build_caustica, n)
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("build/nanoflann/photons:" + size).c_str(), build_nanoflann, n)
            ->Unit(benchmark::kMillisecond);
        for (std::uint32_t k : {50u, 200u})
            for (bool tile : {true, false}) {
                const std::string suffix =
                    "/photons:" + size + "/k:" + std::to_string(k) + "/order:" + (tile ? "tile" : "random");
                benchmark::RegisterBenchmark(("knn/caustica" + suffix).c_str(), knn_caustica, n, k, tile)
                    ->Unit(benchmark::kMillisecond);
                benchmark::RegisterBenchmark(("knn/nanoflann" + suffix).c_str(), knn_nanoflann, n, k, tile)
                    ->Unit(benchmark::kMillisecond);
            }
        for (std::uint32_t k : {5u, 100u})
            for (bool tile : {true, false}) {
                const std::string suffix =
                    "/photons:" + size + "/k:" + std::to_string(k) + "/order:" + (tile ? "tile" : "random");
                benchmark::RegisterBenchmark(("always_k/caustica" + suffix).c_str(), always_k_caustica, n, k, tile)
                    ->Unit(benchmark::kMillisecond);
                benchmark::RegisterBenchmark(("always_k/nanoflann" + suffix).c_str(), always_k_nanoflann, n, k, tile)
                    ->Unit(benchmark::kMillisecond);
            }
    }
    return 0;
}();

}  // namespace

BENCHMARK_MAIN();
