// The hashed photon grid of the progressive passes against a brute-force gather: the same photons
// counted (exactly), the same power summed (to float rounding), with the side test and the inner
// disc, for radii from a hair to many cells, in clusters and with every photon at one point.
#include "core/photons/photon_grid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

using namespace caustica;

namespace {

std::vector<Photon> clustered_photons(std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> gauss(0.0f, 1.0f);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<Photon> photons(n);
    for (Photon& p : photons) {
        const float r = u(rng);
        if (r < 0.5f)
            p.position = {0.6f + 0.03f * gauss(rng), 0.0f, 0.04f * gauss(rng)};  // a focus on a floor
        else if (r < 0.8f)
            p.position = {u(rng) * 2.0f - 1.0f, 0.5f, u(rng) * 2.0f - 1.0f};  // a ceiling
        else
            p.position = {u(rng) * 4.0f - 2.0f, u(rng) * 2.0f - 1.0f, -1.0f};  // a wall
        p.power = {u(rng), u(rng), u(rng)};
        p.direction = glm::normalize(glm::vec3(gauss(rng), gauss(rng), gauss(rng)));
    }
    return photons;
}

PhotonGrid::Gather brute_force(const std::vector<Photon>& photons, const glm::vec3& p, const glm::vec3& n, float radius) {
    PhotonGrid::Gather g;
    const float r2 = radius * radius;
    for (const Photon& photon : photons) {
        const glm::vec3 d = photon.position - p;
        const float d2 = glm::dot(d, d);
        if (!(d2 < r2) || !(glm::dot(photon.direction, n) < 0.0f)) continue;
        g.sum += photon.power;
        ++g.count;
        if (d2 < 0.5f * r2) g.inner += photon.power;
    }
    return g;
}

void expect_same(const PhotonGrid::Gather& got, const PhotonGrid::Gather& want, const char* what) {
    EXPECT_EQ(got.count, want.count) << what;
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(got.sum[c], want.sum[c], 1e-4f * (1.0f + want.sum[c])) << what;
        EXPECT_NEAR(got.inner[c], want.inner[c], 1e-4f * (1.0f + want.inner[c])) << what;
    }
}

}  // namespace

TEST(PhotonGrid, GathersWhatABruteForceGathers) {
    const std::vector<Photon> photons = clustered_photons(20000, 1);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (float cell : {0.004f, 0.02f, 0.1f}) {
        PhotonGrid grid;
        grid.build(photons, cell);
        ASSERT_EQ(grid.size() >= photons.size(), true);
        for (int q = 0; q < 400; ++q) {
            // Queries near the photons (on the floor, the ceiling and the wall) and anywhere.
            const glm::vec3 near = photons[static_cast<std::size_t>(q * 37) % photons.size()].position;
            const glm::vec3 p = q % 4 == 3 ? glm::vec3(u(rng), u(rng), u(rng)) : near + 0.01f * glm::vec3(u(rng), u(rng), u(rng));
            const glm::vec3 n = glm::normalize(glm::vec3(u(rng), u(rng), u(rng)) + glm::vec3(0.0f, 0.01f, 0.0f));
            // Radii within one cell, a few cells, and many.
            for (float radius : {0.3f * cell, 0.5f * cell, 2.0f * cell, 0.15f}) {
                expect_same(grid.gather(p, n, radius), brute_force(photons, p, n, radius), "clustered");
                if (HasFailure()) return;
            }
        }
    }
}

TEST(PhotonGrid, CollidingCellsAreCountedOnce) {
    // A small table: many cells share a bucket. A disc over several cells of one bucket must
    // still count each photon once.
    std::vector<Photon> photons;
    for (int i = 0; i < 64; ++i)
        for (int j = 0; j < 64; ++j)
            photons.push_back({glm::vec3(0.01f * i, 0.0f, 0.01f * j), glm::vec3(1.0f), glm::vec3(0, -1, 0)});
    PhotonGrid grid;
    grid.build(photons, 0.005f);
    for (float radius : {0.004f, 0.02f, 0.2f, 2.0f}) {
        const glm::vec3 p(0.3f, 0.0f, 0.3f), n(0, 1, 0);
        expect_same(grid.gather(p, n, radius), brute_force(photons, p, n, radius), "grid of photons");
    }
}

TEST(PhotonGrid, EdgeCases) {
    PhotonGrid empty;
    empty.build({}, 0.1f);
    EXPECT_EQ(empty.gather(glm::vec3(0.0f), glm::vec3(0, 1, 0), 1.0f).count, 0u);
    // Every photon at one point; a zero radius finds nothing; photons arriving from behind are skipped.
    std::vector<Photon> one_point(1000, Photon{glm::vec3(0.5f), glm::vec3(0.25f), glm::vec3(0, -1, 0)});
    one_point[7].direction = glm::vec3(0, 1, 0);
    PhotonGrid grid;
    grid.build(one_point, 0.1f);
    const PhotonGrid::Gather g = grid.gather(glm::vec3(0.5f), glm::vec3(0, 1, 0), 0.01f);
    EXPECT_EQ(g.count, 999u);
    EXPECT_NEAR(g.sum.x, 999 * 0.25f, 1e-2f);
    EXPECT_EQ(grid.gather(glm::vec3(0.5f), glm::vec3(0, 1, 0), 0.0f).count, 0u);
    // Far coordinates stay finite and found.
    std::vector<Photon> far = {{glm::vec3(1e7f, -1e7f, 3e6f), glm::vec3(1.0f), glm::vec3(0, -1, 0)}};
    grid.build(far, 0.01f);
    EXPECT_EQ(grid.gather(glm::vec3(1e7f, -1e7f, 3e6f), glm::vec3(0, 1, 0), 1.0f).count, 1u);
}

TEST(PhotonGrid, CellsFarSmallerThanTheRadiusGatherEverythingWithoutOverflow) {
    // Cells of 1e-9 and a radius of 1: some 2e9 cells an axis, whose product passes 2^63; the
    // gather scans every bucket instead, and finds what a brute force finds.
    std::vector<Photon> photons;
    for (int i = 0; i < 200; ++i)
        photons.push_back({glm::vec3(0.01f * i - 1.0f, 0.003f * i, -0.5f), glm::vec3(1.0f), glm::vec3(0, -1, 0)});
    PhotonGrid grid;
    grid.build(photons, 1e-9f);
    for (const glm::vec3 p : {glm::vec3(0.0f), glm::vec3(-1.0f, 0.2f, -0.5f)})
        expect_same(grid.gather(p, glm::vec3(0, 1, 0), 1.0f), brute_force(photons, p, glm::vec3(0, 1, 0), 1.0f),
                    "tiny cells");
}

TEST(PhotonGrid, TheSameBitsEveryBuild) {
    const std::vector<Photon> photons = clustered_photons(50000, 3);
    PhotonGrid a, b;
    a.build(photons, 0.01f);
    b.build(photons, 0.01f);
    b.build(clustered_photons(1000, 4), 0.03f);  // a reused grid rebuilt for other photons
    b.build(photons, 0.01f);
    for (int q = 0; q < 200; ++q) {
        const glm::vec3 p = photons[static_cast<std::size_t>(q) * 101].position;
        const PhotonGrid::Gather x = a.gather(p, glm::vec3(0, 1, 0), 0.008f), y = b.gather(p, glm::vec3(0, 1, 0), 0.008f);
        EXPECT_EQ(std::memcmp(&x, &y, sizeof x), 0) << q;
    }
}
