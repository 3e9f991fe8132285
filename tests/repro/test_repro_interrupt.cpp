// The reproducer of the third hardening audit's I1 (tests/repro/README.md): one cancel, the
// preview's or Ctrl-C in `caustica render` (which passes it to the session within 50 ms), stops a
// render within a bound however long one packet, one ray or one photon takes (docs/RELIABILITY.md,
// "Bounded time"). Each test starts, in this process, a render whose stage under test would go on
// for seconds more, cancels it once that stage is under way and times the session's return.
#include "tests/repro/repro_runner.h"

#include "core/lua/scene_loader.h"
#include "core/render/render_session.h"
#include "tests/scene_test_helpers.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

using namespace caustica;
using caustica::repro::repro_source;
using caustica::testing::time_bound;

namespace {

/// From cancel() to wait()'s return, on the reference machine (tests/time_bounds.h): the ray
/// being traced stops at its next sphere or CSG leaf, a tile or a photon loop right after it.
constexpr double cancel_bound_seconds = 0.25;

using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
    return std::chrono::duration<double>(clock_type::now() - t0).count();
}

/// What a session did with one cancel.
struct CancelOutcome {
    bool in_stage = false;      ///< the render was in the stage under test when cancelled
    double seconds = 0.0;       ///< from cancel() to wait()'s return
    bool completed = true;      ///< what wait() returned
    bool reported_cancelled = false;
};

/// Starts `job`, waits until the session's progress names `stage`, lets the stage run 0.2 s (into
/// its first packets or photon blocks, each of which lasts seconds), cancels once and times wait().
CancelOutcome cancel_during(RenderSession& session, const RenderJob& job, const std::string& stage) {
    session.set_job(job);
    session.start();
    const auto started = clock_type::now();
    while (session.progress().running && session.progress().stage != stage &&
           seconds_since(started) < time_bound(60.0))
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    CancelOutcome outcome;
    const SessionProgress before = session.progress();
    outcome.in_stage = before.running && before.stage == stage;
    const auto t0 = clock_type::now();
    session.cancel();
    outcome.completed = session.wait();
    outcome.seconds = seconds_since(t0);
    outcome.reported_cancelled = session.progress().cancelled;
    return outcome;
}

void expect_stopped_at_once(const CancelOutcome& o, const std::string& stage) {
    ASSERT_TRUE(o.in_stage) << "the render was not in '" << stage << "' when cancelled";
    EXPECT_FALSE(o.completed);
    EXPECT_TRUE(o.reported_cancelled);
    EXPECT_LE(o.seconds, time_bound(cancel_bound_seconds)) << "in '" << stage << "'";
}

/// 2^16 unit spheres in a CSG union, each level the union of the one below and its copy shifted
/// by 0.001: one object, one Embree primitive, whose every ray evaluates 65 536 leaves.
RenderJob deep_union_job() {
    return caustica::testing::load_first_job(R"(
local m = gr.material({0.8,0.2,0.2},{0,0,0},10)
local s = gr.sphere('s') s:set_material(m)
local cur = s
for i = 1, 16 do
  local b = gr.node('b' .. i) b:add_child(cur) b:translate(0.001, 0, 0)
  cur = gr.union('u' .. i, cur, b)
end
local root = gr.node('root') root:add_child(cur)
gr.render(root, 'x.png', 16, 16, {0,0,5}, {0,0,-1}, {0,1,0}, 50, {0.1,0.1,0.1}, {gr.light({5,5,5},{1,1,1},{1,0,0})})
)");
}

/// 2^16 overlapping glass spheres (as in interrupt/overlapping_spheres.lua) around a point light
/// at their common centre: every photon ray starts inside all of them and meets every one, and
/// bounces from one surface to the next. `options` go to gr.option.
RenderJob glass_around_light_job(const std::string& options) {
    return caustica::testing::load_first_job("gr.option('" + options + "')\n" + R"(
local glass = gr.material({0,0,0},{0.9,0.9,0.9},20)
glass:set_ri(1.5)
local function with_shifted_copy(node, i)
  local copy = gr.node('copy' .. i) copy:add_child(node) copy:translate(0.001, 0, 0)
  local both = gr.node('both' .. i) both:add_child(node) both:add_child(copy)
  return both
end
local cur = gr.sphere('s') cur:set_material(glass)
for i = 1, 16 do cur = with_shifted_copy(cur, i) end
gr.render(cur, 'x.png', 16, 16, {0,0,5}, {0,0,-1}, {0,1,0}, 50, {0.1,0.1,0.1}, {gr.light({0,0,0},{1,1,1},{1,0,1})})
)");
}

}  // namespace

// Every camera packet meets 262 144 spheres: the one 16 x 16 tile takes seconds. The cancel stops
// the packet at its next sphere, and the tile it cut short is never published: a viewer keeps
// the image it has.
TEST(ReproTime, I1_OneCancelStopsACameraPacketThroughOverlappingSpheres) {
    const RenderJob job = load_scene_script(repro_source("interrupt/overlapping_spheres.lua").string()).renders.at(0);
    RenderSession session;
    expect_stopped_at_once(cancel_during(session, job, "first samples"), "first samples");
    Image shown;
    std::vector<std::uint64_t> seen;
    EXPECT_EQ(session.fetch_tiles(shown, seen), 0u);
}

TEST(ReproTime, I1_OneCancelStopsARayThroughADeepCsgUnion) {
    RenderSession session;
    expect_stopped_at_once(cancel_during(session, deep_union_job(), "first samples"), "first samples");
}

// The photon stage of either integrator, every photon traced (no projection map).
TEST(ReproTime, I1_OneCancelStopsClassicPhotonsThroughOverlappingGlass) {
    RenderSession session;
    const RenderJob job = glass_around_light_job("--caustic-num-photons 1000000 --projection-map off");
    expect_stopped_at_once(cancel_during(session, job, "shooting photons"), "shooting photons");
}

TEST(ReproTime, I1_OneCancelStopsProgressivePhotonsThroughOverlappingGlass) {
    RenderSession session;
    const RenderJob job =
        glass_around_light_job("--integrator progressive --caustic-num-photons 1000000 --projection-map off");
    expect_stopped_at_once(cancel_during(session, job, "shooting photons"), "shooting photons");
}

// The classic photon stage starts with the light's projection map: 64 800 rays from the light.
TEST(ReproTime, I1_OneCancelStopsAProjectionMapThroughOverlappingGlass) {
    RenderSession session;
    const RenderJob job = glass_around_light_job("--caustic-num-photons 1000000");
    expect_stopped_at_once(cancel_during(session, job, "shooting photons"), "shooting photons");
}
