// The classic photon pass and the classic k-NN search and estimate (docs/CAUSTICS.md, from
// "photon emission" to "estimate"): each rule of the original renderer, with a test that fails
// without it.
#include "core/integrators/registry.h"
#include "core/photons/caustic_stage.h"
#include "core/photons/classic_photons.h"
#include "core/photons/photon_kdtree.h"
#include "core/photons/photon_map.h"
#include "core/scene/scene_flatten.h"
#include "core/scene/source_location.h"
#include "tests/test_support.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace caustica;
using caustica::testing::JobBuilder;

namespace {

constexpr double pi = 3.14159265358979323846;

MaterialDesc material(glm::dvec3 kd, glm::dvec3 ks = glm::dvec3(0.0), bool reflective = false) {
    MaterialDesc m;
    m.kd = kd;
    m.ks = ks;
    m.reflective = reflective;
    return m;
}

int add_material(JobBuilder& b, const MaterialDesc& m) {
    b.scene->materials.push_back(m);
    return static_cast<int>(b.scene->materials.size()) - 1;
}

/// A closed box of six thin slabs around the origin (half width w, half height h): the floor
/// (y = -h), the ceiling (y = +h) and the four walls, with a light at the origin of falloff
/// (0, 0, c2). `walls` null leaves the sides open.
JobBuilder box_scene(const MaterialDesc& floor, const MaterialDesc& ceiling, const MaterialDesc* walls, double w = 1.0,
                     double h = 1.0, glm::dvec3 colour = glm::dvec3(1.0), double c2 = 1.0) {
    JobBuilder b(8, 8);
    const double t = 0.01, over = 1.05;
    const int f = b.add(NodeKind::cube, add_material(b, floor));
    b.translate(f, {0, -h, 0});
    b.scale(f, {w * over, t, w * over});
    const int c = b.add(NodeKind::cube, add_material(b, ceiling));
    b.translate(c, {0, h, 0});
    b.scale(c, {w * over, t, w * over});
    if (walls) {
        const int m = add_material(b, *walls);
        for (int side = -1; side <= 1; side += 2) {
            const int x = b.add(NodeKind::cube, m);
            b.translate(x, {side * w, 0, 0});
            b.scale(x, {t, h * over, w * over});
            const int z = b.add(NodeKind::cube, m);
            b.translate(z, {0, 0, side * w});
            b.scale(z, {w * over, h * over, t});
        }
    }
    b.light({0, 0, 0}, colour, {0, 0, c2});
    return b;
}

std::unique_ptr<RenderScene> build_scene(const RenderJob& job) {
    return std::make_unique<RenderScene>(*job.scene, flatten_scene(*job.scene, job.root, false));
}

ClassicPhotonResult shoot(const RenderJob& job, long long caustic, long long gi, std::uint64_t seed = 1,
                          ProjectionMapMode mode = ProjectionMapMode::automatic) {
    const auto scene = build_scene(job);
    ClassicPhotonSettings s;
    s.caustic_photons = caustic;
    s.gi_photons = gi;
    s.unit_distance = job.options.unit_distance;
    s.energy_fudge = job.options.energy_fudge;
    s.projection_map = mode;
    s.seed = seed;
    return shoot_classic_photons(*scene, nullptr, job_lights(job), s, nullptr);
}

/// The energy of one photon ("photon emission"), in double: 4 pi d_u^2 fudge C / (c2 N).
glm::dvec3 expected_energy(glm::dvec3 colour, double unit_distance, double fudge, double c2, double n) {
    return 4.0 * pi * unit_distance * unit_distance * fudge * colour / (c2 * n);
}

void expect_near_rel(const glm::vec3& got, const glm::dvec3& want, double rel) {
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(got[i], want[i], rel * std::fabs(want[i])) << "channel " << i;
}

/// The uniform numbers a stream will give, without consuming the stream.
std::vector<double> peek(RandomStream stream, int count) {
    std::vector<double> xi(static_cast<std::size_t>(count));
    for (double& x : xi) x = stream.uniform();
    return xi;
}

}  // namespace

// ---- emission cells --------------------------------------------------------------------------

TEST(ClassicEmission, CellsTileTheSphereWithNearlyEqualSolidAngles) {
    double total = 0.0, smallest = 1e9, largest = 0.0;
    for (long long cell = 0; cell < classic_emission_cells; ++cell) {
        glm::dvec3 a, b, c;
        classic_emission_cell(cell, a, b, c);
        const double omega = spherical_triangle_solid_angle(a, b, c);
        total += omega;
        smallest = std::min(smallest, omega);
        largest = std::max(largest, omega);
    }
    EXPECT_NEAR(total, 4.0 * pi, 1e-8);  // the cells cover the sphere exactly once
    std::printf("cell solid angle: min %.4g max %.4g (mean %.4g), ratio %.3f\n", smallest, largest,
                4.0 * pi / classic_emission_cells, largest / smallest);
    // Midpoints pushed onto the sphere at every level: nearly even cells, the largest 1.301 times
    // the smallest (projecting a flat subdivision only at the end would give 1.98).
    EXPECT_NEAR(largest / smallest, 1.301, 0.001);
}

TEST(ClassicEmission, ShotCountsAreTheOriginalsExactly) {
    // floor(N a_T) summed over the geodesic cells: the totals the original shot, to the
    // photon. A flat subdivision projected at the end gives other totals (2 035 060 at 2 621 440).
    EXPECT_EQ(classic_photons_offered(2'621'440), 1'638'400);
    EXPECT_EQ(classic_photons_offered(4'000'000), 3'041'280);
    EXPECT_EQ(classic_photons_offered(8'000'000), 7'055'360);
    EXPECT_EQ(classic_photons_offered(24'000'000), 23'436'800);
    // Below one photon per cell the literal floor would shoot nothing under N = 1 / (largest a_T)
    // = 1 086 326 (the default --gi-num-photons included): there each cell's share is rounded at
    // random, so about N are shot. A sum of 1 310 720 roundings has a standard deviation below
    // sqrt(1 310 720 / 4) = 572: allow 5 of them.
    double largest = 0.0;
    for (long long cell = 0; cell < classic_emission_cells; ++cell) {
        glm::dvec3 a, b, c;
        classic_emission_cell(cell, a, b, c);
        largest = std::max(largest, spherical_triangle_solid_angle(a, b, c) / (4.0 * pi));
    }
    EXPECT_EQ(static_cast<long long>(std::ceil(1.0 / largest)), 1086326);
    for (long long n : {1'000LL, 1'000'000LL, classic_emission_cells - 1})
        EXPECT_NEAR(static_cast<double>(classic_photons_offered(n)), static_cast<double>(n), 5.0 * 572.0) << n;
    // From one photon per cell on, the literal floor: a quarter of the cells reach 1.
    EXPECT_EQ(classic_photons_offered(classic_emission_cells), 327'680);
}

TEST(ClassicEmission, ThePassTracesEveryPhotonTheCellsOffer) {
    // A light between a floor and a ceiling: every offered photon is traced (GI has no map).
    const MaterialDesc grey = material({0.5, 0.5, 0.5});
    const RenderJob job = box_scene(grey, grey, nullptr, 1.0, 1.0).build();
    const long long n = 2'000'000;
    const ClassicPhotonResult r = shoot(job, 0, n);
    ASSERT_EQ(r.gi_lights.size(), 1u);
    EXPECT_EQ(r.gi_lights[0].candidates, classic_photons_offered(n));
    EXPECT_EQ(r.gi_lights[0].traced, classic_photons_offered(n));
}

// ---- The photon rules ------------------------------------------------------------------------

TEST(ClassicPhotons, EnergyIsSetByThePhotonsRequestedNotShot) {
    // A white mirror floor (always specular) under a light in a closed box of diffuse walls: every
    // photon stored carries eps ks kd with eps = 4 pi d_u^2 fudge C / (c2 N).
    const MaterialDesc mirror = material({0, 0, 0}, {1, 1, 1}, true);
    const MaterialDesc wall = material({0.5, 0.25, 1.0});
    JobBuilder b = box_scene(mirror, wall, &wall, 2.0, 2.0, {1.0, 2.0, 0.5}, 0.25);
    b.job.options.unit_distance = 2.0;
    b.job.options.energy_fudge = 1.5;
    const long long n = 1'500'000;
    const ClassicPhotonResult r = shoot(b.build(), n, 0);
    const glm::dvec3 eps = expected_energy({1.0, 2.0, 0.5}, 2.0, 1.5, 0.25, static_cast<double>(n));
    ASSERT_GT(r.caustic.size(), 10000u);
    const long long offered = classic_photons_offered(n);
    EXPECT_LT(offered, n * 0.9) << "the test needs the shot count to differ from N";
    glm::dvec3 total(0.0);
    for (const Photon& p : r.caustic) total += glm::dvec3(p.power);
    const glm::dvec3 want = eps * glm::dvec3(0.5, 0.25, 1.0);
    expect_near_rel(glm::vec3(total / static_cast<double>(r.caustic.size())), want, 1e-5);
    expect_near_rel(r.caustic.front().power, want, 1e-6);
}

TEST(ClassicPhotons, SpecularOddsAreTheLumaOfKs) {
    // A mirror floor in a box of grey walls; the projection map keeps the photons near it. Each
    // photon that chooses specular at the mirror is stored once on a wall. Against a white mirror
    // (every photon chooses specular) with the same seed, the fraction kept is the luma of ks,
    // 0.4566, not its mean 0.433 (22 standard deviations away, see below).
    const glm::dvec3 ks(0.9, 0.3, 0.1);
    const MaterialDesc wall = material({0.5, 0.5, 0.5});
    const long long n = 2'000'000;
    const auto white = shoot(box_scene(material({0, 0, 0}, {1, 1, 1}, true), wall, &wall).build(), n, 0);
    const auto tinted = shoot(box_scene(material({0, 0, 0}, ks, true), wall, &wall).build(), n, 0);
    ASSERT_TRUE(white.caustic_lights[0].projection_map_used);
    EXPECT_LT(white.caustic_lights[0].occupied_fraction, 0.35);  // the floor and its margin only
    const double all = static_cast<double>(white.caustic.size());
    const double fraction = static_cast<double>(tinted.caustic.size()) / all;
    const double y = 0.299 * 0.9 + 0.587 * 0.3 + 0.114 * 0.1;
    const double sd = std::sqrt(y * (1.0 - y) / all);  // binomial: about 0.001 for 220 000 photons
    std::printf("specular odds: %.5f of %.0f (luma %.5f, sd %.5f)\n", fraction, all, y, sd);
    EXPECT_NEAR(fraction, y, 5.0 * sd);
    // Power after the mirror is power ks, not divided by P(specular): eps ks kd on the wall.
    const glm::dvec3 eps = expected_energy(glm::dvec3(1.0), 1.0, 1.0, 1.0, static_cast<double>(n));
    for (const Photon& p : tinted.caustic) expect_near_rel(p.power, eps * ks * 0.5, 1e-6);
}

TEST(ClassicPhotons, DiffuseOddsAreTheLumaOfKdAndKdPlusKsMayExceedOne) {
    // GI: a diffuse floor in a box of nearly black walls (kd 1e-6: photons stop there but stored
    // power is not zero). A photon that chooses diffuse at the floor is stored once on a wall, or,
    // when its direction points into the floor (the lobe is not clipped), once on a dark block
    // that fills the floor slab's lower half.
    const glm::dvec3 kd(0.9, 0.3, 0.1);
    const MaterialDesc dark = material(glm::dvec3(1e-6));
    const long long n = 1'500'000;
    const auto room = [&](const MaterialDesc& floor) {
        JobBuilder b = box_scene(floor, dark, &dark);
        const int block = b.add(NodeKind::cube, add_material(b, dark));
        b.translate(block, {0, -1 - 5, 0});  // top at y = -1, the middle of the floor slab
        b.scale(block, {1.1, 5, 1.1});
        return b.build();
    };
    const auto white = shoot(room(material({1, 1, 1})), 0, n);
    const auto tinted = shoot(room(material(kd)), 0, n);
    const double all = static_cast<double>(white.gi.size());
    const double fraction = static_cast<double>(tinted.gi.size()) / all;
    const double y = 0.299 * 0.9 + 0.587 * 0.3 + 0.114 * 0.1;
    const double sd = std::sqrt(y * (1.0 - y) / all);
    std::printf("diffuse odds: %.5f of %.0f (luma %.5f, sd %.5f)\n", fraction, all, y, sd);
    EXPECT_NEAR(fraction, y, 5.0 * sd);
    // (Power after a diffuse bounce, kd not divided by P(diffuse): GiStoreRuleFollowsDiffuseChoicesOnly.)
    // Cumulative odds: Y(kd) = 0.7 and Y(ks) = 0.6 on a mirror: diffuse below 0.7, specular
    // between 0.7 and 1.3, so specular with probability 0.3 (the original's rule; progressive
    // refuses such a material).
    const MaterialDesc wall = material({0.5, 0.5, 0.5});
    const auto both = shoot(box_scene(material(glm::dvec3(0.7), glm::dvec3(0.6), true), wall, &wall).build(), n, 0);
    const auto mirror = shoot(box_scene(material({0, 0, 0}, {1, 1, 1}, true), wall, &wall).build(), n, 0);
    const double specular = static_cast<double>(both.caustic.size()) / static_cast<double>(mirror.caustic.size());
    EXPECT_NEAR(specular, 0.3, 5.0 * std::sqrt(0.21 / static_cast<double>(mirror.caustic.size())));
}

namespace {

/// Materials for the single-photon tests: a white mirror floor (kd 0: always specular, never
/// stored) and a ceiling that is diffuse with kd and a white mirror otherwise.
struct MirrorPair {
    RenderJob job;
    std::unique_ptr<RenderScene> scene;
    double p_diffuse;
};

MirrorPair mirror_pair(glm::dvec3 ceiling_kd, bool walls) {
    const MaterialDesc black = material({0, 0, 0});
    JobBuilder b = box_scene(material({0, 0, 0}, {1, 1, 1}, true), material(ceiling_kd, {1, 1, 1}, true),
                             walls ? &black : nullptr, 50.0, 1.0);
    MirrorPair m{b.build(), nullptr, classic_luma(glm::vec3(ceiling_kd))};
    m.scene = build_scene(m.job);
    return m;
}

}  // namespace

TEST(ClassicPhotons, CausticStoreRuleAndContinuationOnlyOnSpecular) {
    // A photon shot straight down bounces between the white mirror floor and the ceiling (kd, else
    // a white mirror). Each ceiling hit after a specular choice stores power kd, whatever it
    // chooses; the first diffuse choice ends the path. One uniform number per hit decides, so the
    // whole path is known from the stream: hits 1, 3, 5... are the floor, 2, 4, ... the ceiling.
    const glm::dvec3 kd(0.2, 0.4, 0.6);
    const MirrorPair m = mirror_pair(kd, false);
    const glm::vec3 power(1.0f, 2.0f, 4.0f);
    int capped = 0, ended_by_diffuse = 0;
    for (int photon = 0; photon < 400; ++photon) {
        for (float start : {-1.0f, 1.0f}) {  // down to the floor first, or up to the ceiling first
            RandomStream random(7, photon, start > 0 ? 1 : 0);
            const std::vector<double> xi = peek(random, classic_max_hits);
            // Predicted: the hit index (1-based) of the first diffuse ceiling choice.
            int hits = classic_max_hits, stores = 0;
            bool specular = false;
            for (int hit = 1; hit <= classic_max_hits; ++hit) {
                const bool ceiling = (hit % 2 == 0) == (start < 0);
                if (!ceiling) {
                    specular = true;
                    continue;
                }
                if (specular) ++stores;
                if (xi[hit - 1] < m.p_diffuse) {
                    hits = hit;
                    break;
                }
                specular = true;
            }
            std::vector<Photon> out;
            const int made = trace_classic_photon(*m.scene, nullptr, ClassicMapKind::caustic,
                                                  Ray{{0, 0, 0}, {0, start, 0}, 0.0f, ray_infinity}, power, random, out);
            ASSERT_EQ(made, hits) << photon;
            ASSERT_EQ(static_cast<int>(out.size()), stores) << photon;
            for (const Photon& p : out) {
                EXPECT_NEAR(p.position.y, 1.0f - 0.01f, 1e-4f);  // on the ceiling's underside
                expect_near_rel(p.power, glm::dvec3(power) * kd, 1e-6);  // power kd; the white mirrors keep it
            }
            (hits == classic_max_hits ? capped : ended_by_diffuse) += 1;
        }
    }
    EXPECT_GT(ended_by_diffuse, 100);
    EXPECT_GT(capped, 0);
}

TEST(ClassicPhotons, AtMostThirteenHits) {
    // A closed box of white mirrors with kd 0.01: a photon chooses diffuse with probability 0.01
    // per hit and specular otherwise, so nothing but the cap stops most paths. The caustic photon
    // is stored at every hit after the first: 12 photons for a capped path.
    const MaterialDesc mirror = material(glm::dvec3(0.01), {1, 1, 1}, true);
    const RenderJob job = box_scene(mirror, mirror, &mirror).build();
    const auto scene = build_scene(job);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int capped = 0;
    for (int photon = 0; photon < 500; ++photon) {
        glm::vec3 d(u(rng), u(rng), u(rng));
        d = glm::normalize(d);
        RandomStream random(11, photon);
        const std::vector<double> xi = peek(random, classic_max_hits);
        int expected = classic_max_hits;
        for (int hit = 1; hit <= classic_max_hits; ++hit)
            if (xi[hit - 1] < classic_luma(glm::vec3(0.01f))) {
                expected = hit;
                break;
            }
        std::vector<Photon> out;
        const int hits = trace_classic_photon(*scene, nullptr, ClassicMapKind::caustic, Ray{{0, 0, 0}, d, 0.0f, ray_infinity},
                                              glm::vec3(1.0f), random, out);
        ASSERT_EQ(hits, expected) << photon;
        ASSERT_EQ(static_cast<int>(out.size()), hits - 1) << photon;
        capped += hits == classic_max_hits;
    }
    EXPECT_GT(capped, 400);  // 0.99^13 = 88% reach the cap
}

TEST(ClassicPhotons, GiStoreRuleFollowsDiffuseChoicesOnly) {
    // GI between a white diffuse floor (always diffuse) and a grey ceiling (kd 0.5, else absorbed),
    // open at the sides: every hit after the first is stored with the product of the kd met so far.
    const MaterialDesc grey = material({0.5, 0.5, 0.5});
    JobBuilder b = box_scene(material({1, 1, 1}), grey, nullptr, 50.0, 1.0);
    const RenderJob job = b.build();
    const auto scene = build_scene(job);
    int stored_total = 0;
    for (int photon = 0; photon < 300; ++photon) {
        RandomStream random(5, photon);
        std::vector<Photon> out;
        const int hits = trace_classic_photon(*scene, nullptr, ClassicMapKind::gi, Ray{{0, 0, 0}, {0, -1, 0}, 0.0f, ray_infinity},
                                              glm::vec3(1.0f), random, out);
        // Open sides: a path may leave the box, so it holds at least the first hit.
        ASSERT_GE(hits, 1);
        ASSERT_EQ(static_cast<int>(out.size()), hits - 1) << photon;
        float expected = 1.0f;  // power after the first (white) diffuse choice
        for (const Photon& p : out) {
            const bool ceiling = p.position.y > 0.0f;
            expected *= ceiling ? 0.5f : 1.0f;  // stored power: power kd of this hit
            EXPECT_FLOAT_EQ(p.power.x, expected);
        }
        stored_total += static_cast<int>(out.size());
    }
    EXPECT_GT(stored_total, 300);
    // A specular choice is not a diffuse one: straight down onto a mirror (kd 0.1, else specular),
    // straight up to the grey ceiling, the photon is not stored there unless it chose diffuse at
    // the mirror first (then it leaves the vertical and hits the ceiling elsewhere).
    JobBuilder m = box_scene(material(glm::dvec3(0.1), {1, 1, 1}, true), grey, nullptr, 50.0, 1.0);
    const RenderJob mirror_job = m.build();
    const auto mirror_scene = build_scene(mirror_job);
    int specular_first = 0;
    for (int photon = 0; photon < 300; ++photon) {
        RandomStream random(6, photon);
        const double xi = peek(random, 1)[0];
        std::vector<Photon> out;
        trace_classic_photon(*mirror_scene, nullptr, ClassicMapKind::gi, Ray{{0, 0, 0}, {0, -1, 0}, 0.0f, ray_infinity},
                             glm::vec3(1.0f), random, out);
        if (xi < classic_luma(glm::vec3(0.1f))) continue;
        ++specular_first;
        for (const Photon& p : out)
            EXPECT_FALSE(p.position.y > 0.0f && std::hypot(p.position.x, p.position.z) < 1e-3f)
                << "stored at the ceiling after a specular choice only";
    }
    EXPECT_GT(specular_first, 200);
}

TEST(ClassicPhotons, GiMapReplacesNothingInTheCausticMap) {
    const MaterialDesc wall = material({0.5, 0.5, 0.5});
    const RenderJob job = box_scene(material({0.2, 0.2, 0.2}, {0.7, 0.7, 0.7}, true), wall, &wall).build();
    const auto without = shoot(job, 1'500'000, 0);
    const auto with = shoot(job, 1'500'000, 1'500'000);
    ASSERT_EQ(without.caustic.size(), with.caustic.size());
    for (std::size_t i = 0; i < with.caustic.size(); ++i) {
        ASSERT_EQ(without.caustic[i].position, with.caustic[i].position);
        ASSERT_EQ(without.caustic[i].power, with.caustic[i].power);
    }
    EXPECT_TRUE(without.gi.empty());
    EXPECT_GT(with.gi.size(), with.caustic.size());  // diffuse walls everywhere: GI photons abound
}

TEST(ClassicPhotons, ReproducibleForAnyThreadCount) {
    const MaterialDesc wall = material({0.5, 0.5, 0.5});
    const RenderJob job = box_scene(material({0.2, 0.2, 0.2}, {0.7, 0.7, 0.7}, true), wall, &wall).build();
    auto run = [&](int threads) {
        tbb::task_arena arena(threads);
        ClassicPhotonResult r;
        arena.execute([&] { r = shoot(job, 1'400'000, 1'400'000); });
        return r;
    };
    const ClassicPhotonResult one = run(1), two = run(2);
    ASSERT_EQ(one.caustic.size(), two.caustic.size());
    ASSERT_EQ(one.gi.size(), two.gi.size());
    for (std::size_t i = 0; i < one.gi.size(); ++i) ASSERT_EQ(one.gi[i].position, two.gi[i].position);
    for (std::size_t i = 0; i < one.caustic.size(); ++i) ASSERT_EQ(one.caustic[i].position, two.caustic[i].position);
}

TEST(ClassicPhotons, DiffuseDirectionsSpreadAroundTheMirrorDirection) {
    // Normal incidence: the mirror direction is the normal and sin(alpha) is uniform on [0, 1]
    // (not cos-weighted): its quartiles are 0.25, 0.5 and 0.75.
    const glm::vec3 n(0, 1, 0);
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> sines;
    for (int i = 0; i < 40000; ++i) {
        const glm::vec3 d = classic_diffuse_direction({0, -1, 0}, n, u(rng), u(rng));
        ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f);
        sines.push_back(std::sqrt(std::max(0.0f, 1.0f - d.y * d.y)));
    }
    std::sort(sines.begin(), sines.end());
    for (int q = 1; q <= 3; ++q) EXPECT_NEAR(sines[sines.size() * q / 4], 0.25f * q, 0.01f) << q;
    // Grazing incidence: the mirror direction lies in the surface, and by symmetry half of the
    // lobe points below it. The lobe is not clipped: those go on into the solid.
    const int grazing = 40000;
    int below = 0;
    for (int i = 0; i < grazing; ++i) below += glm::dot(classic_diffuse_direction({1, 0, 0}, n, u(rng), u(rng)), n) < 0.0f;
    EXPECT_NEAR(static_cast<double>(below) / grazing, 0.5, 5.0 * 0.5 / std::sqrt(grazing));
}

TEST(ClassicPhotons, ProjectionMapKeepsDirectionsWhoseFirstHitHasKsLumaAboveAFifth) {
    JobBuilder b(8, 8);
    struct Target {
        glm::dvec3 centre;
        MaterialDesc material;
        bool used;
    };
    MaterialDesc glass = material({0, 0, 0}, glm::dvec3(0.15));
    glass.refractive_index = 1.5;
    const Target targets[] = {
        {{3, 0, 0}, material({0, 0, 0}, {0, 0.4, 0}, true), true},    // Y 0.235 (mean 0.133)
        {{-3, 0, 0}, material({0, 0, 0}, {0, 0, 1}, true), false},    // a mirror, Y 0.114 (mean 0.333)
        {{0, 0, 3}, material({0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}), true}, // not a mirror, but Y 0.5
        {{0, 0, -3}, glass, false},                                   // glass, Y 0.15
    };
    for (const Target& t : targets) {
        const int node = b.add(NodeKind::sphere, add_material(b, t.material));
        b.translate(node, t.centre);
        b.scale(node, glm::dvec3(0.5));
    }
    b.light({0, 0, 0}, {1, 1, 1}, {0, 0, 1});
    const RenderJob job = b.build();
    const auto scene = build_scene(job);
    ProjectionMap map(180);
    map.build(*scene, {0, 0, 0}, classic_projection_target);
    for (const Target& t : targets)
        EXPECT_EQ(map.occupied(glm::normalize(glm::vec3(t.centre))), t.used) << t.centre.x << " " << t.centre.z;
    EXPECT_FALSE(map.occupied({0, 1, 0}));  // nothing above
    // The pass uses it: only photons towards the two used spheres are traced.
    const ClassicPhotonResult r = shoot(job, 2'000'000, 0);
    EXPECT_TRUE(r.caustic_lights[0].projection_map_used);
    EXPECT_LT(r.caustic_lights[0].traced, r.caustic_lights[0].candidates / 20);
    EXPECT_GT(r.caustic_lights[0].traced, 0);
}

// ---- Search and estimate ---------------------------------------------------------------------

TEST(ClassicSearch, AlwaysReturnsKEvenWhenEveryPhotonIsFar) {
    std::vector<glm::vec3> points;
    for (int i = 0; i < 500; ++i) points.push_back({10.0f + 0.01f * i, 0.0f, 0.0f});
    const PhotonKdTree tree(points);
    std::vector<Neighbour> result(100);
    for (std::uint32_t k : {1u, 5u, 100u}) {
        ASSERT_EQ(tree.nearest_always({0, 0, 0}, k, 0.15f, result.data()), k);
        EXPECT_EQ(tree.nearest({0, 0, 0}, k, 0.15f, result.data()), 0u) << "the progressive search finds none";
    }
    // Fewer stored than k: all of them.
    const PhotonKdTree few(std::vector<glm::vec3>{{5, 0, 0}, {6, 0, 0}, {7, 0, 0}});
    EXPECT_EQ(few.nearest_always({0, 0, 0}, 100, 0.15f, result.data()), 3u);
    EXPECT_EQ(PhotonKdTree(std::vector<glm::vec3>{}).nearest_always({0, 0, 0}, 5, 0.15f, result.data()), 0u);
}

TEST(ClassicSearch, EqualsBruteForceWhenTheKNearestLieWithinThePruneDistance) {
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<glm::vec3> points(30000);
    for (glm::vec3& p : points) p = {u(rng), 0.02f * u(rng), u(rng)};
    const PhotonKdTree tree(points);
    std::vector<Neighbour> result(100);
    int checked = 0;
    for (int query = 0; query < 300; ++query) {
        const glm::vec3 q(u(rng), 0.0f, u(rng));
        std::vector<float> all;
        for (const glm::vec3& p : points) all.push_back(glm::dot(p - q, p - q));
        std::sort(all.begin(), all.end());
        for (std::uint32_t k : {5u, 100u}) {
            const float prune = 0.15f;
            const std::uint32_t found = tree.nearest_always(q, k, prune, result.data());
            ASSERT_EQ(found, k);
            if (all[k - 1] >= prune * prune) continue;  // beyond the prune distance: not promised
            std::vector<float> got;
            for (std::uint32_t i = 0; i < found; ++i) got.push_back(result[i].distance2);
            std::sort(got.begin(), got.end());
            ASSERT_EQ(got, std::vector<float>(all.begin(), all.begin() + k)) << query << " k " << k;
            ++checked;
        }
    }
    EXPECT_GT(checked, 500);
}

TEST(ClassicSearch, EstimateIsPowerOverTheDiscOfTheFarthestReturned) {
    // Five photons at distances 0.1, 0.2, 0.3, 0.4 and 2 from p, on both sides of any surface.
    const std::vector<Photon> photons = {
        {{0.1f, 0, 0}, {1, 0, 0}, {0, -1, 0}},
        {{0, 0.2f, 0}, {0, 2, 0}, {0, 1, 0}},  // arriving from below: still counted
        {{0, 0, 0.3f}, {0, 0, 3}, {0, -1, 0}},
        {{-0.4f, 0, 0}, {4, 0, 0}, {0, -1, 0}},
        {{2, 0, 0}, {100, 100, 100}, {0, -1, 0}},
    };
    const PhotonMap map(photons);
    std::vector<Neighbour> scratch(10);
    const ClassicEstimate three = map.classic_estimate({0, 0, 0}, 3, 0.15f, scratch.data());
    EXPECT_EQ(three.photons, 3u);
    EXPECT_NEAR(three.radius, 0.3f, 1e-6f);
    EXPECT_NEAR(three.value.x, 1.0f / (pi * 0.09), 1e-3f);
    EXPECT_NEAR(three.value.y, 2.0f / (pi * 0.09), 1e-3f);
    EXPECT_NEAR(three.value.z, 3.0f / (pi * 0.09), 1e-3f);
    // k above the photons stored: all five, r = 2.
    const ClassicEstimate all = map.classic_estimate({0, 0, 0}, 10, 0.15f, scratch.data());
    EXPECT_EQ(all.photons, 5u);
    EXPECT_NEAR(all.value.x, 105.0f / (pi * 4.0), 1e-3f);
    // No photons, or r = 0: 0.
    EXPECT_EQ(PhotonMap(std::vector<Photon>{}).classic_estimate({0, 0, 0}, 5, 0.15f, scratch.data()).value, glm::vec3(0.0f));
    EXPECT_EQ(map.classic_estimate({0.1f, 0, 0}, 1, 0.15f, scratch.data()).value, glm::vec3(0.0f));
    // The nearest photon, however far.
    float distance = 0.0f;
    const Photon* nearest = map.nearest_photon({3, 0, 0}, &distance);
    ASSERT_NE(nearest, nullptr);
    EXPECT_EQ(nearest->power, glm::vec3(100.0f));
    EXPECT_NEAR(distance, 1.0f, 1e-6f);
    EXPECT_EQ(PhotonMap(std::vector<Photon>{}).nearest_photon({0, 0, 0}), nullptr);
}

// ---- the stage -------------------------------------------------------------------------------

TEST(ClassicStage, FingerprintFollowsIntegratorAndGi) {
    const MaterialDesc grey = material({0.5, 0.5, 0.5});
    JobBuilder b = box_scene(grey, grey, &grey);  // nothing specular
    b.job.options.caustic_num_photons = 1'000'000;
    RenderJob job = b.build();
    job.options.integrator = IntegratorKind::classic;
    EXPECT_FALSE(caustics_needed(job));
    job.options.gi = true;
    EXPECT_TRUE(caustics_needed(job)) << "GI needs no specular object";
    const std::uint64_t classic_gi = caustic_fingerprint(job, 1);
    job.options.gi_num_photons = 2'000'000;
    const std::uint64_t more_gi = caustic_fingerprint(job, 1);
    EXPECT_NE(classic_gi, more_gi);
    job.options.gi = false;
    job.options.draw_gi_only = true;  // also wants the GI map: same stage as --gi
    EXPECT_EQ(caustic_fingerprint(job, 1), more_gi);
    job.options.draw_gi_only = false;
    const std::uint64_t classic_plain = caustic_fingerprint(job, 1);
    EXPECT_NE(classic_plain, more_gi);
    job.options.integrator = IntegratorKind::progressive;
    EXPECT_NE(caustic_fingerprint(job, 1), classic_plain);
    job.options.gi = true;
    EXPECT_TRUE(caustics_needed(job)) << "progressive --gi: one map of every indirect path";
}

TEST(ClassicStage, BuildsTheMapsOfTheIntegratorAndAcceptsKdPlusKsAboveOne) {
    const MaterialDesc wall = material({0.5, 0.5, 0.5});
    JobBuilder b = box_scene(material({0.7, 0.7, 0.7}, {0.6, 0.6, 0.6}, true), wall, &wall);
    b.job.options.caustic_num_photons = 1'500'000;
    b.job.options.gi = true;
    b.job.options.gi_num_photons = 1'400'000;
    RenderJob job = b.build();
    const auto scene = build_scene(job);
    CausticStage stage;
    build_caustic_stage(stage, *scene, job, nullptr);
    ASSERT_TRUE(stage.map && stage.gi_map);
    EXPECT_GT(stage.map->size(), 1000u);
    EXPECT_GT(stage.gi_map->size(), stage.map->size());
    ASSERT_EQ(stage.lights.size(), 1u);
    ASSERT_EQ(stage.gi_lights.size(), 1u);
    EXPECT_EQ(stage.lights[0].candidates, classic_photons_offered(1'500'000));
    EXPECT_EQ(stage.gi_lights[0].traced, classic_photons_offered(1'400'000));
    EXPECT_EQ(stage.lights[0].stored, static_cast<long long>(stage.map->size()));
    job.options.integrator = IntegratorKind::progressive;  // mean(kd) + mean(ks) = 1.3 on a mirror
    CausticStage progressive;
    EXPECT_THROW(build_caustic_stage(progressive, *scene, job, nullptr), InputError);
}
