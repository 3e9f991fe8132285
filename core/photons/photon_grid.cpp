#include "core/photons/photon_grid.h"

#include "core/render/random.h"
#include "core/util/huge_pages.h"
#include "core/util/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace caustica {
namespace {

// Buckets hold their photons in runs padded to whole lanes: a scan is a loop of full vectors.
constexpr std::uint32_t lanes = 8;
// Padding photons lie far outside any gather.
constexpr float far_away = std::numeric_limits<float>::max();

typedef float Lanes __attribute__((vector_size(lanes * sizeof(float))));
// A block: 8 photons' x, y, z, r, g, b, direction x, y, z, 8 floats each.
constexpr std::size_t block_floats = 9 * lanes;

/// A cell coordinate, kept finite and within a range the hash mixes well.
std::int64_t cell_coordinate(float x, float inverse_cell) {
    const double c = std::floor(static_cast<double>(x) * static_cast<double>(inverse_cell));
    return static_cast<std::int64_t>(std::clamp(c, -1e15, 1e15));
}

// The AVX2 and baseline versions of scan_runs and the loader's choice between them (an ifunc).
// Not under ThreadSanitizer: its runtime is not up when the loader runs the chooser, which then
// crashes the program before main; the baseline alone there.
#if defined(__SANITIZE_THREAD__)
#define CAUSTICA_SCAN_CLONES
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define CAUSTICA_SCAN_CLONES
#endif
#endif
#ifndef CAUSTICA_SCAN_CLONES
#define CAUSTICA_SCAN_CLONES __attribute__((target_clones("avx2", "default")))
#endif

struct Scan {
    Lanes sum_r, sum_g, sum_b, inner_r, inner_g, inner_b, count;
};

/// Scans the runs (block ranges) of `blocks`: the lane sums of the photons within r2 of p arriving
/// against n (and within r2 / 2). Compiled twice, for AVX2 and for the baseline, the right one
/// chosen when the program loads; the sums are the same bits either way (each lane adds its own
/// photons in order, the lanes are added at the end in a fixed order).
CAUSTICA_SCAN_CLONES void scan_runs(const float* blocks, const std::uint32_t* runs,
                                                                  int run_count, const glm::vec3& p, const glm::vec3& n,
                                                                  float r2, Scan& out) {
    const Lanes px = {p.x, p.x, p.x, p.x, p.x, p.x, p.x, p.x}, py = {p.y, p.y, p.y, p.y, p.y, p.y, p.y, p.y},
                pz = {p.z, p.z, p.z, p.z, p.z, p.z, p.z, p.z};
    const Lanes nx = {n.x, n.x, n.x, n.x, n.x, n.x, n.x, n.x}, ny = {n.y, n.y, n.y, n.y, n.y, n.y, n.y, n.y},
                nz = {n.z, n.z, n.z, n.z, n.z, n.z, n.z, n.z};
    const float h2 = 0.5f * r2;
    const Lanes outer = {r2, r2, r2, r2, r2, r2, r2, r2}, inner = {h2, h2, h2, h2, h2, h2, h2, h2};
    const Lanes zero = {}, one = zero + 1.0f;
    Scan s{zero, zero, zero, zero, zero, zero, zero};
    for (int run = 0; run < run_count; ++run) {
        for (std::uint32_t block = runs[2 * run]; block < runs[2 * run + 1]; ++block) {
            const float* f = blocks + static_cast<std::size_t>(block) * block_floats;
            Lanes x, y, z, r, g, b, dx, dy, dz;
            std::memcpy(&x, f, sizeof x);
            std::memcpy(&y, f + lanes, sizeof y);
            std::memcpy(&z, f + 2 * lanes, sizeof z);
            std::memcpy(&r, f + 3 * lanes, sizeof r);
            std::memcpy(&g, f + 4 * lanes, sizeof g);
            std::memcpy(&b, f + 5 * lanes, sizeof b);
            std::memcpy(&dx, f + 6 * lanes, sizeof dx);
            std::memcpy(&dy, f + 7 * lanes, sizeof dy);
            std::memcpy(&dz, f + 8 * lanes, sizeof dz);
            const Lanes ex = x - px, ey = y - py, ez = z - pz;
            const Lanes d2 = ex * ex + ey * ey + ez * ez;
            const auto front = dx * nx + dy * ny + dz * nz < zero;
            const Lanes w = ((d2 < outer) & front) ? one : zero, wi = ((d2 < inner) & front) ? one : zero;
            s.sum_r += w * r;
            s.sum_g += w * g;
            s.sum_b += w * b;
            s.inner_r += wi * r;
            s.inner_g += wi * g;
            s.inner_b += wi * b;
            s.count += w;
        }
    }
    out = s;
}

float lane_total(const Lanes& v) {
    float t = 0.0f;
    for (std::uint32_t i = 0; i < lanes; ++i) t += v[i];
    return t;
}

}  // namespace

std::uint64_t PhotonGrid::bucket_of(std::int64_t i, std::int64_t j, std::int64_t k) const {
    // Cells are hashed by blocks of 2 x 2 x 2 whose 8 buckets are adjacent: the cells a gather
    // overlaps mostly share a block, so their run starts share a cache line.
    const std::uint64_t h = static_cast<std::uint64_t>(i >> 1) * 0x9E3779B185EBCA87ULL ^
                            static_cast<std::uint64_t>(j >> 1) * 0xC2B2AE3D27D4EB4FULL ^
                            static_cast<std::uint64_t>(k >> 1) * 0x165667B19E3779F9ULL;
    const std::uint64_t within = static_cast<std::uint64_t>((i & 1) | ((j & 1) << 1) | ((k & 1) << 2));
    return ((mix64(h) << 3) | within) & mask_;
}

void PhotonGrid::build(const std::vector<Photon>& photons, float cell) {
    cell_ = cell > 0.0f && std::isfinite(cell) ? cell : 1.0f;
    inverse_cell_ = 1.0f / cell_;
    const std::size_t n = photons.size();
    std::uint64_t buckets = 16;
    while (buckets < n) buckets *= 2;
    mask_ = buckets - 1;
    // Each photon's bucket (in parallel), then a counting sort in photon order (deterministic).
    // Room for a quarter more than this pass needs: the next pass, a few photons larger, then
    // grows in place instead of moving to fresh pages (slow to fault in on some machines:
    // docs/PERFORMANCE.md).
    auto room = [](auto& v, std::size_t size) {
        if (size > v.capacity()) reserve_huge(v, size + size / 4);
        v.resize(size);
    };
    room(scratch_, n);
    caustica::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const glm::vec3& q = photons[i].position;
            scratch_[i] = static_cast<std::uint32_t>(bucket_of(cell_coordinate(q.x, inverse_cell_),
                                                               cell_coordinate(q.y, inverse_cell_),
                                                               cell_coordinate(q.z, inverse_cell_)));
        }
    });
    // Per bucket its photons (cursor_) and its blocks (start_), from one count.
    cursor_.assign(buckets + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++cursor_[scratch_[i] + 1];
    start_.resize(buckets + 1);
    start_[0] = 0;
    std::uint64_t total = 0, first = 0;
    for (std::uint64_t b = 1; b <= buckets; ++b) {
        const std::uint32_t count = cursor_[b];
        total += (count + lanes - 1) / lanes;
        first += count;
        start_[b] = static_cast<std::uint32_t>(total);
        cursor_[b] = static_cast<std::uint32_t>(first);
    }
    // The photons' indices bucket by bucket, in photon order within each (a stable counting sort
    // of 4-byte indices: the random writes stay in a small array)...
    room(order_, n);
    for (std::size_t i = 0; i < n; ++i) order_[cursor_[scratch_[i]]++] = static_cast<std::uint32_t>(i);
    // (cursor_[b] is now bucket b's end, the next one's start: shifted back.)
    for (std::uint64_t b = buckets; b > 0; --b) cursor_[b] = cursor_[b - 1];
    cursor_[0] = 0;
    // ... then the blocks written in order, each whole, in parallel over the buckets: every block
    // has one place, so the layout is the same on any thread count. The last block of a bucket
    // is padded with photons far away that arrive from nowhere (direction 0): never gathered.
    room(blocks_, total * block_floats);
    caustica::parallel_for(tbb::blocked_range<std::uint64_t>(0, buckets, 4096), [&](const tbb::blocked_range<std::uint64_t>& range) {
        for (std::uint64_t bucket = range.begin(); bucket != range.end(); ++bucket) {
            const std::uint32_t begin = cursor_[bucket], end = cursor_[bucket + 1];
            float* f = blocks_.data() + static_cast<std::size_t>(start_[bucket]) * block_floats;
            for (std::uint32_t slot = begin; slot < end; slot += lanes, f += block_floats) {
                const std::uint32_t filled = std::min<std::uint32_t>(lanes, end - slot);
                for (std::uint32_t lane = 0; lane < filled; ++lane) {
                    const Photon& photon = photons[order_[slot + lane]];
                    const float values[9] = {photon.position.x, photon.position.y, photon.position.z,
                                             photon.power.x,    photon.power.y,    photon.power.z,
                                             photon.direction.x, photon.direction.y, photon.direction.z};
                    for (int c = 0; c < 9; ++c) f[c * lanes + lane] = values[c];
                }
                for (std::uint32_t lane = filled; lane < lanes; ++lane)
                    for (int c = 0; c < 9; ++c) f[c * lanes + lane] = c < 3 ? far_away : 0.0f;
            }
        }
    });
    photons_ = n;
}

PhotonGrid::Gather PhotonGrid::gather(const glm::vec3& p, const glm::vec3& n, float radius) const {
    Gather g;
    if (photons_ == 0 || !(radius > 0.0f)) return g;
    // The buckets of the cells the sphere of `radius` overlaps, each once.
    const std::int64_t lo[3] = {cell_coordinate(p.x - radius, inverse_cell_), cell_coordinate(p.y - radius, inverse_cell_),
                                cell_coordinate(p.z - radius, inverse_cell_)};
    const std::int64_t hi[3] = {cell_coordinate(p.x + radius, inverse_cell_), cell_coordinate(p.y + radius, inverse_cell_),
                                cell_coordinate(p.z + radius, inverse_cell_)};
    constexpr int max_inline = 64;
    std::uint64_t inline_buckets[max_inline];
    std::vector<std::uint64_t> many;
    std::uint64_t* buckets = inline_buckets;
    // In floating point: the coordinates are clamped, not small, so the product can pass 2^63.
    const double cells_real = static_cast<double>(hi[0] - lo[0] + 1) * static_cast<double>(hi[1] - lo[1] + 1) *
                              static_cast<double>(hi[2] - lo[2] + 1);
    const std::int64_t cells = cells_real > static_cast<double>(mask_ + 1) ? static_cast<std::int64_t>(mask_ + 2)
                                                                          : static_cast<std::int64_t>(cells_real);
    if (cells > max_inline) {
        many.resize(static_cast<std::size_t>(std::min<std::int64_t>(cells, static_cast<std::int64_t>(mask_ + 1))));
        buckets = many.data();
    }
    std::size_t count = 0;
    if (cells > static_cast<std::int64_t>(mask_ + 1)) {  // more cells than buckets: every bucket
        for (std::uint64_t b = 0; b <= mask_; ++b) buckets[count++] = b;
    } else {
        for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
            for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
                for (std::int64_t k = lo[2]; k <= hi[2]; ++k) buckets[count++] = bucket_of(i, j, k);
        if (count <= 8) {  // the usual case: drop repeats in place, keeping the cells' order
            std::size_t kept = 0;
            for (std::size_t c = 0; c < count; ++c) {
                bool seen = false;
                for (std::size_t d = 0; d < kept; ++d) seen |= buckets[d] == buckets[c];
                if (!seen) buckets[kept++] = buckets[c];
            }
            count = kept;
        } else {
            std::sort(buckets, buckets + count);
            count = static_cast<std::size_t>(std::unique(buckets, buckets + count) - buckets);
        }
    }
    // The runs of the non-empty buckets, in bucket order.
    std::uint32_t inline_runs[2 * max_inline];
    std::vector<std::uint32_t> many_runs;
    std::uint32_t* runs = inline_runs;
    if (count > static_cast<std::size_t>(max_inline)) {
        many_runs.resize(2 * count);
        runs = many_runs.data();
    }
    int run_count = 0;
    for (std::size_t b = 0; b < count; ++b) {
        const std::uint32_t first = start_[buckets[b]], last = start_[buckets[b] + 1];
        if (first == last) continue;
        runs[2 * run_count] = first;
        runs[2 * run_count + 1] = last;
        ++run_count;
    }
    Scan s;
    scan_runs(blocks_.data(), runs, run_count, p, n, radius * radius, s);
    g.sum = glm::vec3(lane_total(s.sum_r), lane_total(s.sum_g), lane_total(s.sum_b));
    g.inner = glm::vec3(lane_total(s.inner_r), lane_total(s.inner_g), lane_total(s.inner_b));
    g.count = static_cast<std::uint32_t>(lane_total(s.count));
    return g;
}

std::size_t PhotonGrid::memory_bytes() const {
    return (start_.capacity() + scratch_.capacity() + cursor_.capacity() + order_.capacity()) * sizeof(std::uint32_t) +
           blocks_.capacity() * sizeof(float);
}

}  // namespace caustica
