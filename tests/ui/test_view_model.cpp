// The preview's model without GL: loading, live knobs that redo only what they invalidate
// (checked with the session's stage counters), scene errors that keep the previous scene,
// reloading on file changes, reverting settings that fail to render, saving, arguments.
#include "ui/camera_input.h"
#include "ui/view_arguments.h"
#include "ui/view_model.h"
#include "ui_test_support.h"

#include "core/io/png_io.h"
#include "core/render/orbit_target.h"
#include "core/scene/camera.h"
#include "core/scene/source_location.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>

namespace caustica::ui {
namespace {

using namespace caustica::ui::testing;

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tolerance = 1e-9) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

/// Checks that `point` lies on the view axis of `camera`.
void expect_on_axis(const glm::dvec3& point, const CameraDesc& camera) {
    const glm::dvec3 view = glm::normalize(camera.view);
    expect_near(point, camera.eye + view * glm::dot(point - camera.eye, view));
}

ModelConfig test_config() {
    ModelConfig config;
    config.option_tokens = {"--reproducible", "--threads", "2"};
    return config;  // no recent file
}

/// A model showing a finished render of the test scene.
struct LoadedModel {
    TempFolder folder;
    std::string scene;
    ViewModel model{test_config()};

    explicit LoadedModel(const std::string& text = caustic_box_text()) {
        scene = folder.write("scene.lua", text);
        model.open(scene);
        EXPECT_TRUE(run_until_finished(model)) << model.error();
    }
};

TEST(ViewModel, LoadsInTheBackgroundAndRendersTheScriptsView) {
    LoadedModel m;
    EXPECT_TRUE(m.model.has_scene());
    EXPECT_EQ(m.model.scene_path(), m.scene);
    EXPECT_EQ(m.model.driver().image().width, 256);
    EXPECT_EQ(m.model.driver().image().height, 192);
    EXPECT_FALSE(m.model.orbit_camera().moved());
    EXPECT_EQ(m.model.driver().job().camera.eye, glm::dvec3(0.0, 1.6, 4.6));
    const auto counters = m.model.stage_counters();
    EXPECT_EQ(counters.scene_builds, 1);
    EXPECT_EQ(counters.photon_passes, 1);
    EXPECT_TRUE(m.model.error().empty());
}

TEST(ViewModel, CameraMovesNeitherRebuildNorReshoot) {
    LoadedModel m;
    const auto before = m.model.stage_counters();
    m.model.orbit(20.0, 5.0);
    m.model.zoom(2.0);
    m.model.pan({10.0, -4.0});
    ASSERT_TRUE(run_until_finished(m.model));
    const auto after = m.model.stage_counters();
    EXPECT_EQ(after.scene_builds, before.scene_builds);
    EXPECT_EQ(after.photon_passes, before.photon_passes);
    EXPECT_GT(after.renders, before.renders);
    EXPECT_TRUE(m.model.orbit_camera().moved());
}

TEST(ViewModel, NeighboursAndMaxDistanceOnlyGatherAgain) {
    LoadedModel m;
    const auto before = m.model.stage_counters();
    CausticKnobs k = m.model.knobs();
    k.num_neighbours = 40;
    m.model.set_knobs(k);
    ASSERT_TRUE(run_until_finished(m.model));
    k.max_dist = 0.05;
    m.model.set_knobs(k);
    ASSERT_TRUE(run_until_finished(m.model));
    const auto after = m.model.stage_counters();
    EXPECT_EQ(after.photon_passes, before.photon_passes);
    EXPECT_EQ(after.scene_builds, before.scene_builds);
    EXPECT_EQ(after.renders, before.renders + 2);
    EXPECT_EQ(m.model.driver().job().options.caustic_num_neighbours, 40);
    EXPECT_EQ(m.model.driver().job().options.caustic_max_dist, 0.05);
}

TEST(ViewModel, PhotonKnobsShootAgainWithoutRebuildingTheScene) {
    LoadedModel m;
    const auto before = m.model.stage_counters();
    CausticKnobs k = m.model.knobs();
    k.num_photons = 500000;
    m.model.set_knobs(k);
    ASSERT_TRUE(run_until_finished(m.model));
    k.unit_distance = 2.0;
    m.model.set_knobs(k);
    ASSERT_TRUE(run_until_finished(m.model));
    const auto after = m.model.stage_counters();
    EXPECT_EQ(after.photon_passes, before.photon_passes + 2);
    EXPECT_EQ(after.scene_builds, before.scene_builds);
}

TEST(ViewModel, SwitchingIntegratorReshootsWithoutRebuildingAndSurvivesAReload) {
    LoadedModel m;
    EXPECT_EQ(m.model.knobs().integrator, IntegratorKind::classic);  // the default
    EXPECT_EQ(m.model.driver().stats().integrator, "classic");
    const auto before = m.model.stage_counters();
    CausticKnobs k = m.model.knobs();
    k.integrator = IntegratorKind::progressive;
    m.model.set_knobs(k);
    m.model.set_stop_rules({2, 0.0, 0.0});  // the preview refines without end unless told
    ASSERT_TRUE(run_until_finished(m.model));
    EXPECT_EQ(m.model.driver().accumulation().passes_done, 2);
    const auto after = m.model.stage_counters();
    EXPECT_EQ(after.photon_passes, before.photon_passes + 1);
    EXPECT_EQ(after.scene_builds, before.scene_builds);
    EXPECT_EQ(m.model.driver().stats().integrator, "progressive");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    m.folder.write("scene.lua", caustic_box_text(300000));
    ASSERT_TRUE(run_until(m.model, [&] {
        return m.model.driver().job().options.caustic_num_photons == 300000 && m.model.driver().finished();
    }, 30.0));
    EXPECT_EQ(m.model.driver().job().options.integrator, IntegratorKind::progressive);  // the person's choice stays
}

TEST(ViewModel, DisplaySettingsAndOverlayNeverRender) {
    LoadedModel m;
    const std::uint64_t restarts = m.model.driver().restarts();
    m.model.display().exposure = 2.0f;
    m.model.display().srgb = true;
    m.model.set_overlay({true, true, 0});
    ASSERT_TRUE(run_until(m.model, [&] { return m.model.overlay_settled(); }));
    EXPECT_EQ(m.model.driver().restarts(), restarts);
}

TEST(ViewModel, OverlayTracesTheMapOfTheLastPhotonPass) {
    LoadedModel m;
    m.model.set_overlay({true, true, 0});
    ASSERT_TRUE(run_until(m.model, [&] { return m.model.overlay_settled() && m.model.overlay_version() > 0; }));
    ASSERT_EQ(m.model.driver().projection_maps().size(), 1u);
    const OverlayImage& image = m.model.overlay_image();
    EXPECT_GT(image.outline.size(), 20u);
    EXPECT_GT(image.cells.size(), 20u);
    EXPECT_NE(m.model.overlay_note().find("outline segments"), std::string::npos);
    // A camera move reprojects without tracing again.
    const glm::vec2 first = image.outline[0];
    m.model.orbit(15.0, 0.0);
    ASSERT_TRUE(run_until_finished(m.model));
    ASSERT_TRUE(run_until(m.model, [&] { return m.model.overlay_settled(); }));
    EXPECT_NE(m.model.overlay_image().outline[0], first);
}

TEST(ViewModel, OverlayExplainsWhyItIsEmpty) {
    LoadedModel m(caustic_box_text(0));
    m.model.set_overlay({true, false, 0});
    m.model.update();
    EXPECT_NE(m.model.overlay_note().find("photons are off"), std::string::npos);
    EXPECT_TRUE(m.model.overlay_image().outline.empty());
}

TEST(ViewModel, ScriptErrorIsShownWithItsLineAndThePreviousSceneStays) {
    LoadedModel m;
    const std::vector<glm::vec3> shown = m.model.driver().image().pixels;
    const auto scene = m.model.driver().job().scene;
    m.folder.write("scene.lua", "white = gr.material({0.7, 0.7, 0.7}, {0, 0, 0}, 0)\n"
                                "root = gr.node('root')\n"
                                "ball = gr.no_such_call('ball')\n");
    m.model.reload();
    ASSERT_TRUE(run_until(m.model, [&] { return !m.model.loading() && !m.model.error().empty(); }));
    EXPECT_NE(m.model.error().find("scene.lua:3:"), std::string::npos) << m.model.error();
    EXPECT_TRUE(m.model.has_scene());
    EXPECT_EQ(m.model.render_count(), 1);
    ASSERT_TRUE(run_until_finished(m.model));
    EXPECT_EQ(m.model.driver().job().scene, scene);
    EXPECT_EQ(m.model.driver().image().pixels, shown);
}

TEST(ViewModel, ReloadsByItselfWhenTheFileChanges) {
    LoadedModel m;
    const auto first = m.model.driver().job().scene;
    // Same size file or not, a new modification time is enough; make sure the clock moves on.
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    m.folder.write("scene.lua", caustic_box_text(2000000, "white = gr.material({0.9, 0.2, 0.2}, {0, 0, 0}, 0)\n"
                                                          "floor:set_material(white)\n"));
    ASSERT_TRUE(run_until(m.model, [&] { return m.model.driver().job().scene != first && m.model.driver().finished(); }, 30.0));
    EXPECT_TRUE(m.model.error().empty());
    // Only materials changed: the scene is rebuilt, and the photons follow the new geometry key.
    EXPECT_EQ(m.model.stage_counters().scene_builds, 2);
}

TEST(ViewModel, KnobsThePersonSetSurviveAReload) {
    LoadedModel m;
    CausticKnobs k = m.model.knobs();
    k.num_neighbours = 42;
    m.model.set_knobs(k);
    m.model.orbit(10.0, 0.0);
    ASSERT_TRUE(run_until_finished(m.model));
    const glm::dvec3 eye = m.model.orbit_camera().eye();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    m.folder.write("scene.lua", caustic_box_text(300000));
    ASSERT_TRUE(run_until(m.model, [&] {
        return m.model.driver().job().options.caustic_num_photons == 300000 && m.model.driver().finished();
    }, 30.0));
    EXPECT_EQ(m.model.knobs().num_neighbours, 42);
    EXPECT_EQ(m.model.orbit_camera().eye(), eye);  // the orbit is kept too
    m.model.reset_knobs();  // back to the script's value: it sets none, so the option's default (no preset)
    EXPECT_EQ(m.model.knobs().num_neighbours, Options{}.caustic_num_neighbours);
    EXPECT_EQ(m.model.current_job().options.caustic_num_neighbours, 5);
}

TEST(ViewModel, SettingsThatFailToRenderAreTakenBack) {
    // kd + ks > 1 on a mirror only matters once photons are shot, and only to the progressive
    // integrator, which refuses a surface that makes energy (the classic one absorbs the rest
    // of its luma odds and renders it).
    LoadedModel m(caustic_box_text(0, "gr.option('--integrator progressive --passes 2')\n"
                                      "hot = gr.material({0.6, 0.6, 0.6}, {0.8, 0.8, 0.8}, 10)\n"
                                      "hot:set_reflective()\n"
                                      "post:set_material(hot)\n"));
    ASSERT_TRUE(m.model.error().empty());
    CausticKnobs k = m.model.knobs();
    k.num_photons = 10000;
    m.model.set_knobs(k);
    ASSERT_TRUE(run_until(m.model, [&] { return !m.model.error().empty(); }));
    EXPECT_NE(m.model.error().find("scene.lua:"), std::string::npos) << m.model.error();
    EXPECT_NE(m.model.error().find("exceeds 1"), std::string::npos) << m.model.error();
    ASSERT_TRUE(run_until_finished(m.model));
    EXPECT_EQ(m.model.knobs().num_photons, 0);
    EXPECT_EQ(m.model.driver().job().options.caustic_num_photons, 0);
}

TEST(ViewModel, InitialTargetIsOnTheViewAxisAtTheCentreOfWhatIsSeen) {
    LoadedModel m;
    const OrbitCamera& orbit = m.model.orbit_camera();
    const CameraDesc& script = orbit.script_camera();
    const RenderJob& job = m.model.driver().job();
    const double expected = visible_centre_distance(m.model.driver().session(), script, job.width, job.height);
    EXPECT_NEAR(orbit.distance(), expected, 1e-9);
    expect_on_axis(orbit.target(), script);
    // The centre ray from (0, 1.6, 4.6) along (0, -0.4, -1) meets the floor 7.0 away; the floor and
    // the wall seen around it have their centre nearer, above the floor.
    EXPECT_GT(orbit.distance(), 3.0);
    EXPECT_LT(orbit.distance(), (1.6 + 1.0) / (0.4 / std::sqrt(1.16)) - 0.5);
    EXPECT_GT(orbit.target().y, -1.0 + 0.1);
}

TEST(ViewModel, OrbitWhenLoadedTurnsAroundThatTarget) {
    TempFolder folder;
    ViewModel model(test_config());
    model.orbit_when_loaded({30.0, 0.0});
    model.open(folder.write("scene.lua", caustic_box_text()));
    ASSERT_TRUE(run_until_finished(model));
    EXPECT_TRUE(model.orbit_camera().moved());
    const CameraDesc& script = model.orbit_camera().script_camera();
    const RenderJob& job = model.driver().job();
    const double distance = visible_centre_distance(model.driver().session(), script, job.width, job.height);
    EXPECT_NEAR(model.orbit_camera().distance(), distance, 1e-9);
    expect_near(model.orbit_camera().target(), script.eye + glm::normalize(script.view) * distance);
    EXPECT_EQ(model.driver().job().camera.eye, model.orbit_camera().desc().eye);
}

TEST(ViewModel, ADragOfSeventyFivePixelsKeepsTheShippedBoxInView) {
    // scenes/default.lua: a box whose walls span [-2.1, 2.1]^3 around the origin, seen through its
    // open front; the centre ray meets the back wall 9.6 away. Turned around that wall, a 75-pixel
    // drag swings the box's centre 70 pixels (of 512) off its place; turned around the centre of
    // what is seen, the box stays where it was.
    ModelConfig config = test_config();
    for (const char* token : {"--minres", "--caustic-num-photons", "0"}) config.option_tokens.push_back(token);
    ViewModel model(config);
    model.open(std::string(CAUSTICA_SOURCE_DIR) + "/scenes/default.lua");
    ASSERT_TRUE(run_until_finished(model)) << model.error();
    const RenderJob job = model.current_job();
    ASSERT_EQ(job.width, 100);
    const glm::vec3 centre(0.0f);
    const auto centre_pixel = [&](const CameraDesc& camera) {
        glm::vec2 pixel(-1e9f);
        EXPECT_TRUE(Camera(camera, job.width, job.height).project(centre, pixel));
        return pixel;
    };
    const glm::vec2 before = centre_pixel(model.orbit_camera().desc());
    for (const glm::vec2 drag : {glm::vec2(75.0f, 0.0f), glm::vec2(-75.0f, 0.0f), glm::vec2(0.0f, 75.0f),
                                 glm::vec2(0.0f, -75.0f)}) {
        OrbitCamera orbit = model.orbit_camera();
        const glm::dvec2 degrees = drag_orbit(drag);
        orbit.orbit(degrees.x, degrees.y);
        const glm::vec2 after = centre_pixel(orbit.desc());
        EXPECT_LT(glm::length(after - before), 0.05f * job.width) << drag.x << " " << drag.y;
        // And nothing hides it: the first surface towards the centre lies beyond it.
        const glm::vec3 eye(orbit.eye());
        glm::vec3 hit;
        ASSERT_TRUE(model.driver().session().pick(Ray{eye, glm::normalize(centre - eye), 0.0f, ray_infinity}, hit));
        EXPECT_GT(glm::length(hit - eye), glm::length(centre - eye)) << drag.x << " " << drag.y;
    }
}

TEST(ViewModel, DoubleClickTargetIsOnTheSurface) {
    LoadedModel m;
    // The image centre column, near the bottom: the floor.
    ASSERT_TRUE(m.model.set_target_at({128.0f, 180.0f}));
    EXPECT_NEAR(m.model.orbit_camera().target().y, -1.0, 1e-3);
    EXPECT_FALSE(m.model.set_target_at({2.0f, 2.0f}));  // the sky beside the wall's top corner
}

TEST(ViewModel, SaveWritesThePngWithItsParametersAndAsksBeforeReplacing) {
    LoadedModel m;
    const std::string path = m.folder.file("saved.png");
    SaveResult r = m.model.save(path, false);
    ASSERT_EQ(r.outcome, SaveOutcome::written) << r.message;
    const Png8 png = read_png(path);
    EXPECT_EQ(png.width, 256);
    EXPECT_EQ(png.height, 192);
    bool camera = false, source = false, passes = false;
    for (const auto& [key, value] : png.text) {
        camera |= key == "caustica:camera" && value.find("eye 0 1.6 4.6") != std::string::npos;
        source |= key == "Source" && value == m.scene;
        passes |= key == "caustica:passes" && value == "complete";
    }
    EXPECT_TRUE(camera && source && passes);
    r = m.model.save(path, false);
    EXPECT_EQ(r.outcome, SaveOutcome::exists);
    r = m.model.save(path, true);
    EXPECT_EQ(r.outcome, SaveOutcome::written);
    EXPECT_EQ(m.model.save(m.folder.file("saved.jpg"), false).outcome, SaveOutcome::failed);
}

TEST(ViewModel, SavingWhilePhotonsAreShotNamesTheDirectLightImage) {
    // Photons enough that their stage lasts while the direct-light pass is on screen.
    TempFolder folder;
    ViewModel model{test_config()};
    model.open(folder.write("scene.lua", caustic_box_text(20000000)));
    const SessionProgress& p = model.driver().progress();
    ASSERT_TRUE(run_until(model, [&] { return p.running && p.stage == "shooting photons" && p.showing_direct_light; }))
        << model.error();
    EXPECT_EQ(model.passes_text(), "direct light only, photons still being shot");
    const std::string path = folder.file("direct.png");
    const SaveResult r = model.save(path, false);
    ASSERT_EQ(r.outcome, SaveOutcome::written) << r.message;
    std::map<std::string, std::string> text;
    for (const auto& [key, value] : read_png(path).text) text[key] = value;
    EXPECT_EQ(text["caustica:passes"], "direct light only (shooting photons under way)");
}

TEST(ViewModel, SavingTheScriptsNameThroughASymlinkLeadingOutIsRefused) {
    // The scene names 'pics/holiday.png'; the folder the preview runs in holds pics -> ../victim, as
    // an archive restores it. Save proposes the script's name, which lands only inside the current
    // folder (docs/RELIABILITY.md, section 1); a name the user types goes anywhere.
    std::string text = caustic_box_text(20000);
    text.replace(text.find("'caustic_box.png'"), 17, "'pics/holiday.png'");
    const int render_line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + text.find("gr.render("), '\n'));
    LoadedModel m(text);
    const std::string victim = m.folder.write("victim/holiday.png", "PRECIOUS-PHOTO");
    fs::create_directory(m.folder.path() / "work");
    fs::create_directory_symlink(m.folder.path() / "victim", m.folder.path() / "work" / "pics");
    const caustica::testing::InFolder in(m.folder.path() / "work");
    ASSERT_EQ(m.model.default_save_path(), "pics/holiday.png");
    const SaveResult refused = m.model.save("pics/holiday.png", true);
    EXPECT_EQ(refused.outcome, SaveOutcome::failed);
    const std::string located = "scene.lua:" + std::to_string(render_line) + ": gr.render: output 'pics/holiday.png' leads to '";
    EXPECT_NE(refused.message.find(located), std::string::npos) << refused.message;
    std::ifstream kept(victim, std::ios::binary);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), std::istreambuf_iterator<char>()), "PRECIOUS-PHOTO");
    const SaveResult typed = m.model.save(m.folder.file("victim/mine.png"), false);
    EXPECT_EQ(typed.outcome, SaveOutcome::written) << typed.message;
    // With pics a plain folder the script's name is saved there.
    fs::remove(m.folder.path() / "work" / "pics");
    fs::create_directory(m.folder.path() / "work" / "pics");
    const SaveResult plain = m.model.save("pics/holiday.png", false);
    EXPECT_EQ(plain.outcome, SaveOutcome::written) << plain.message;
    EXPECT_TRUE(fs::is_regular_file(m.folder.path() / "work" / "pics" / "holiday.png"));
}

TEST(ViewModel, ResolutionScaleAndThreadsRenderAgainOnly) {
    LoadedModel m;
    const auto before = m.model.stage_counters();
    m.model.set_resolution_scale(0.5);
    m.model.set_threads(1);
    ASSERT_TRUE(run_until_finished(m.model));
    EXPECT_EQ(m.model.driver().image().width, 128);
    EXPECT_EQ(m.model.driver().image().height, 96);
    EXPECT_EQ(m.model.driver().job().options.threads, 1);
    EXPECT_EQ(m.model.stage_counters().photon_passes, before.photon_passes);
    EXPECT_EQ(m.model.stage_counters().scene_builds, before.scene_builds);
}

/// The test scene under the progressive integrator with few photons: passes of a few milliseconds.
std::string progressive_box() { return caustic_box_text(20000, "gr.option('--integrator progressive')\n"); }

/// Runs until everything asked is rendering and its accumulation has averaged `passes` passes.
bool run_until_passes(ViewModel& model, int passes, double seconds = 20.0) {
    return run_until(model, [&] {
        return !model.changes_pending() && model.driver().accumulation().passes_done >= passes;
    }, seconds);
}

/// A model refining the progressive test scene (no stopping rule).
struct RefiningModel {
    TempFolder folder;
    std::string scene;
    ViewModel model;

    explicit RefiningModel(ModelConfig config = test_config()) : model(std::move(config)) {
        scene = folder.write("scene.lua", progressive_box());
        model.open(scene);
        EXPECT_TRUE(run_until_passes(model, 1)) << model.error();
    }
};

TEST(ViewModel, ProgressivePreviewRefinesUntilPausedAndResumesFromItsPasses) {
    RefiningModel m;
    const PreviewDriver& driver = m.model.driver();
    EXPECT_EQ(driver.job().options.passes, 0);  // no rule given: no limit
    EXPECT_TRUE(driver.job().options.accumulates());
    const std::uint64_t restarts = driver.restarts();
    ASSERT_TRUE(run_until_passes(m.model, 4));  // refines by itself, with no request
    EXPECT_EQ(driver.restarts(), restarts);
    EXPECT_FALSE(driver.finished());
    const SessionProgress& a = driver.accumulation();
    EXPECT_GE(a.photons_emitted, 4 * 20000LL);
    EXPECT_EQ(a.samples_per_pixel, a.passes_done);
    EXPECT_GT(a.radius, 0.0);
    EXPECT_TRUE(a.error.known);

    m.model.set_paused(true);
    ASSERT_TRUE(run_until(m.model, [&] { return !driver.busy(); }, 5.0));
    EXPECT_TRUE(m.model.paused());
    const int paused_at = driver.accumulation().passes_done;
    const std::vector<glm::vec3> shown = driver.image().pixels;
    run_until(m.model, [] { return false; }, 0.3);
    EXPECT_EQ(driver.accumulation().passes_done, paused_at);
    EXPECT_EQ(driver.image().pixels, shown);

    const auto counters = m.model.stage_counters();
    m.model.set_paused(false);
    int lowest = paused_at;
    ASSERT_TRUE(run_until(m.model, [&] {
        lowest = std::min(lowest, driver.accumulation().passes_done);
        return driver.accumulation().passes_done >= paused_at + 2;
    }, 20.0));
    EXPECT_EQ(lowest, paused_at);  // continued, never from 0
    EXPECT_EQ(driver.restarts(), restarts);
    EXPECT_EQ(m.model.stage_counters().photon_passes, counters.photon_passes);
    EXPECT_EQ(m.model.stage_counters().scene_builds, counters.scene_builds);
}

TEST(ViewModel, ProgressiveChangesRestartOnlyWhatTheyInvalidate) {
    RefiningModel m;
    const PreviewDriver& driver = m.model.driver();
    ASSERT_TRUE(run_until_passes(m.model, 3));
    const auto before = m.model.stage_counters();
    // Each change starts the accumulation again (the image changes): a new render from pass 0.
    const auto change_and_refine = [&](const std::function<void()>& change) {
        const std::uint64_t restarts = driver.restarts();
        change();
        ASSERT_TRUE(run_until(m.model, [&] { return driver.restarts() > restarts; }, 5.0));
        EXPECT_EQ(driver.accumulation().passes_done, 0);
        ASSERT_TRUE(run_until_passes(m.model, 2));
    };
    change_and_refine([&] { m.model.orbit(10.0, 0.0); });  // camera: the eye side only
    CausticKnobs k = m.model.knobs();
    k.num_neighbours = 40;
    change_and_refine([&] { m.model.set_knobs(k); });  // N: the radius sequence
    k.max_dist = 0.05;
    change_and_refine([&] { m.model.set_knobs(k); });  // max distance: the radius sequence
    auto after = m.model.stage_counters();
    EXPECT_EQ(after.scene_builds, before.scene_builds);
    EXPECT_EQ(after.photon_passes, before.photon_passes);  // the first pass's photons are kept
    k.num_photons = 30000;
    change_and_refine([&] { m.model.set_knobs(k); });  // photons: the photon passes
    after = m.model.stage_counters();
    EXPECT_EQ(after.scene_builds, before.scene_builds);
    EXPECT_EQ(after.photon_passes, before.photon_passes + 1);
    EXPECT_EQ(driver.job().options.caustic_num_photons, 30000);
}

TEST(ViewModel, PassLimitStopsThePreviewAndRaisingItContinues) {
    ModelConfig config = test_config();
    config.option_tokens.insert(config.option_tokens.end(), {"--passes", "3"});
    TempFolder folder;
    ViewModel model(config);
    model.open(folder.write("scene.lua", progressive_box()));
    ASSERT_TRUE(run_until_finished(model, 20.0)) << model.error();
    const PreviewDriver& driver = model.driver();
    EXPECT_EQ(driver.accumulation().passes_done, 3);
    EXPECT_EQ(driver.accumulation().stopped_by, "passes");
    EXPECT_EQ(model.stop_rules(), (StopRules{3, 0.0, 0.0}));
    const std::uint64_t restarts = driver.restarts();
    const auto counters = model.stage_counters();
    model.set_stop_rules({5, 0.0, 0.0});  // continues the same accumulation
    int lowest = 3;
    ASSERT_TRUE(run_until(model, [&] {
        lowest = std::min(lowest, driver.accumulation().passes_done);
        return driver.finished() && driver.accumulation().passes_done == 5;
    }, 20.0));
    EXPECT_EQ(lowest, 3);
    EXPECT_EQ(driver.restarts(), restarts);
    EXPECT_EQ(model.stage_counters().photon_passes, counters.photon_passes);
    EXPECT_EQ(driver.job().options.passes, 5);
    // The person's rules are the progressive integrator's: a classic job keeps the command line's.
    CausticKnobs k = model.knobs();
    k.integrator = IntegratorKind::classic;
    model.set_knobs(k);
    EXPECT_EQ(model.current_job().options.passes, 3);
}

TEST(ViewModel, SaveNamesThePassesOfTheAccumulation) {
    RefiningModel m;
    ASSERT_TRUE(run_until_passes(m.model, 3));
    m.model.set_paused(true);
    ASSERT_TRUE(run_until(m.model, [&] { return !m.model.driver().busy(); }, 5.0));
    const SessionProgress a = m.model.driver().accumulation();
    const std::string path = m.folder.file("refined.png");
    const SaveResult r = m.model.save(path, false);
    ASSERT_EQ(r.outcome, SaveOutcome::written) << r.message;
    EXPECT_NE(r.message.find(std::to_string(a.passes_done) + " passes"), std::string::npos) << r.message;
    std::map<std::string, std::string> text;
    for (const auto& [key, value] : read_png(path).text) text[key] = value;
    EXPECT_EQ(text["caustica:integrator"], "progressive");
    EXPECT_EQ(text["caustica:passes"], std::to_string(a.passes_done));
    EXPECT_EQ(text["caustica:samples-per-pixel"], std::to_string(a.passes_done));
    EXPECT_EQ(text["caustica:pass-limit"], "none");
    EXPECT_EQ(text["caustica:photons-emitted"], std::to_string(a.photons_emitted));
    EXPECT_EQ(text["caustica:state"], "paused");
    const std::string& error = text["caustica:estimated-error"];
    if (a.error.known)  // the relative error as a number (it may exceed 1 early on), then its parts
        EXPECT_NEAR(std::strtod(error.c_str(), nullptr), a.error.relative, 1e-3 * a.error.relative) << error;
    else
        EXPECT_EQ(error.rfind("unknown", 0), 0u) << error;
}

/// The progressive test scene at 64 x 48 pixels (passes of milliseconds), with `rules` for its
/// gr.option.
std::string small_progressive_box(const std::string& rules = "") {
    std::string text = caustic_box_text(20000, "gr.option('--integrator progressive " + rules + "')\n");
    const auto at = text.find("256, 192");
    if (at != std::string::npos) text.replace(at, 8, "64, 48");
    return text;
}

/// Updates until the driver has started another render; false on timeout.
bool run_until_restarted(ViewModel& model, double seconds = 20.0) {
    const std::uint64_t before = model.driver().restarts();
    return run_until(model, [&] { return model.driver().restarts() > before; }, seconds);
}

/// Pauses and waits for the render to stop.
bool pause_and_wait(ViewModel& model) {
    model.set_paused(true);
    return run_until(model, [&] { return !model.driver().busy(); }, 10.0);
}

TEST(ViewModel, UndoingAChangeBringsBackTheAccumulationItRestartedWithItsPassesAndImage) {
    TempFolder folder;
    ViewModel model(test_config());
    model.open(folder.write("scene.lua", small_progressive_box("--passes 12")));
    const PreviewDriver& driver = model.driver();
    ASSERT_TRUE(run_until_finished(model)) << model.error();
    ASSERT_EQ(driver.accumulation().passes_done, 12);
    const std::vector<glm::vec3> finished = driver.image().pixels;

    CausticKnobs k = model.knobs();
    k.num_photons = 30000;  // a change that restarts the accumulation (and shoots photons again)
    model.set_knobs(k);
    ASSERT_TRUE(run_until_passes(model, 1)) << model.error();
    ASSERT_TRUE(pause_and_wait(model));
    ASSERT_LT(driver.accumulation().passes_done, 12) << "the new accumulation overtook the old one";
    EXPECT_EQ(driver.kept_passes(), 12);

    model.undo();
    ASSERT_TRUE(run_until_restarted(model));
    EXPECT_EQ(driver.job().options.caustic_num_photons, 20000);
    EXPECT_EQ(driver.accumulation().passes_done, 12) << "the old accumulation, not a fresh start";
    EXPECT_EQ(driver.kept_passes(), 0) << "the short one it replaced is not worth keeping";
    ASSERT_TRUE(run_until_finished(model)) << model.error();
    EXPECT_EQ(driver.accumulation().passes_done, 12);
    EXPECT_EQ(driver.image().pixels, finished) << "its image, with no pass added or redone";
}

TEST(ViewModel, ACameraThatComesBackContinuesTheAccumulationUntilAFreshOneOvertakesIt) {
    TempFolder folder;
    ViewModel model(test_config());
    model.open(folder.write("scene.lua", small_progressive_box()));
    const PreviewDriver& driver = model.driver();
    ASSERT_TRUE(run_until_passes(model, 9)) << model.error();
    ASSERT_TRUE(pause_and_wait(model));
    const int kept = driver.accumulation().passes_done;

    model.orbit(20.0, 0.0);  // restarts the refinement: the long one is kept
    ASSERT_TRUE(run_until_passes(model, 1)) << model.error();
    ASSERT_TRUE(pause_and_wait(model));
    const int short_one = driver.accumulation().passes_done;
    ASSERT_LT(short_one, kept);
    EXPECT_EQ(driver.kept_passes(), kept);

    model.reset_camera();  // the script's camera again: the kept passes continue
    ASSERT_TRUE(run_until_restarted(model));
    EXPECT_GE(driver.accumulation().passes_done, kept);
    ASSERT_TRUE(run_until_passes(model, kept + 2)) << "it refines on from its passes";

    // A fresh accumulation that gets ahead of the kept one drops it: at most one is kept.
    model.orbit(20.0, 0.0);
    ASSERT_TRUE(run_until_restarted(model));
    EXPECT_GE(driver.kept_passes(), kept + 2);
    const int ahead = driver.kept_passes() + 1;
    ASSERT_TRUE(run_until_passes(model, ahead)) << model.error();
    EXPECT_EQ(driver.kept_passes(), 0);
    ASSERT_TRUE(pause_and_wait(model));
    model.reset_camera();
    ASSERT_TRUE(run_until_restarted(model));
    EXPECT_LT(driver.accumulation().passes_done, ahead) << "nothing kept: the script camera starts again";
}

TEST(ViewModel, AShortAccumulationIsNotKept) {
    TempFolder folder;
    ViewModel model(test_config());
    model.open(folder.write("scene.lua", small_progressive_box("--passes 3")));
    ASSERT_TRUE(run_until_finished(model)) << model.error();
    model.orbit(20.0, 0.0);
    ASSERT_TRUE(run_until_restarted(model));
    EXPECT_EQ(model.driver().kept_passes(), 0);
}

TEST(ViewArguments, ParsesTheViewCommandLine) {
    const ViewArguments a = parse_view_arguments(
        {"scene.lua", "--frames", "12", "--snapshot=out.png", "--overlay", "--orbit", "30,-10.5", "--headless",
         "--reproducible", "--caustic-num-photons", "1000"});
    EXPECT_EQ(a.scene, "scene.lua");
    EXPECT_EQ(a.frames, 12);
    EXPECT_EQ(a.snapshot, "out.png");
    EXPECT_TRUE(a.overlay && a.headless && a.scripted());
    ASSERT_TRUE(a.orbit.has_value());
    EXPECT_EQ(*a.orbit, glm::dvec2(30.0, -10.5));
    EXPECT_EQ(a.option_tokens, (std::vector<std::string>{"--reproducible", "--caustic-num-photons", "1000"}));
    EXPECT_THROW(parse_view_arguments({"--orbit", "30"}), InputError);
    EXPECT_THROW(parse_view_arguments({"--frames", "0"}), InputError);
    EXPECT_THROW(parse_view_arguments({"--snapshot", "x.jpg"}), InputError);
    EXPECT_THROW(parse_view_arguments({"--no-such-option"}), InputError);
    EXPECT_THROW(parse_view_arguments({"a.lua", "b.lua"}), InputError);
    EXPECT_FALSE(parse_view_arguments({}).scripted());
}

std::string argument_error(const std::vector<std::string>& args) {
    try {
        parse_view_arguments(args);
    } catch (const InputError& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(ViewArguments, NonFiniteNumbersAndTwoScenesAreRefusedByName) {
    EXPECT_EQ(argument_error({"--orbit", "nan,0"}), "--orbit nan: expects a finite number");
    EXPECT_EQ(argument_error({"--orbit", "0,inf"}), "--orbit inf: expects a finite number");
    EXPECT_EQ(argument_error({"--orbit=1e999,0"}), "--orbit 1e999: expects a finite number");
    EXPECT_EQ(argument_error({"a.lua", "b.lua"}), "one scene at a time, got 'a.lua' and 'b.lua'");  // main adds "caustica view: "
}

TEST(ViewArguments, SnapshotTargetIsCheckedBeforeRendering) {
    TempFolder folder;
    EXPECT_EQ(snapshot_target_problem(folder.file("shot.png")), "");
    EXPECT_EQ(snapshot_target_problem(folder.file("none/shot.png")),
              folder.file("none/shot.png") + ": the folder " + folder.file("none") + " does not exist");
    std::filesystem::create_directories(folder.file("dir.png"));
    EXPECT_EQ(snapshot_target_problem(folder.file("dir.png")), folder.file("dir.png") + ": is a folder, not a file");
    const std::string plain = folder.write("plain", "x");
    EXPECT_EQ(snapshot_target_problem(plain + "/shot.png"), plain + "/shot.png: " + plain + " is not a folder");
}

TEST(ViewArguments, AScriptedRunEndingWithAnErrorShownExitsTwo) {
    EXPECT_EQ(scripted_exit_code(true, "", false), 0);
    EXPECT_EQ(scripted_exit_code(true, "a.lua:3: gr.render: eye ...", false), 2);  // the scene shown is not the one asked
    EXPECT_EQ(scripted_exit_code(false, "", false), 2);
    EXPECT_EQ(scripted_exit_code(true, "", true), 1);
    // A scene that loads and fails when its render is prepared leaves an error to exit with.
    TempFolder folder;
    const std::string scene = folder.write("far.lua", "local s = gr.sphere('s'); s:set_material(gr.material({0.8, 0.2, 0.2}, {0, 0, 0}, 10))\n"
                                                      "gr.render(s, 'far.png', 8, 8, {0, 0, 1e20}, {0, 0, -1}, {0, 1, 0}, 50, {0.1, 0.1, 0.1}, {})\n");
    ViewModel model(test_config());
    model.open(scene);
    ASSERT_TRUE(run_until(model, [&] { return !model.loading() && !model.error().empty(); }, 30.0));
    EXPECT_EQ(scripted_exit_code(model.has_scene(), model.error(), false), 2) << model.error();
}

}  // namespace
}  // namespace caustica::ui

#include "ui/text_lines.h"

namespace caustica::ui {
namespace {

TEST(StatusLines, BreakOnlyBetweenPartsSoNoNumberIsSplit) {
    const auto measure = [](const std::string& t) { return 7.0f * static_cast<float>(t.size()); };  // 7-pixel characters
    const std::vector<std::string> parts = {"16 of 16 passes", "320M photons", "16 spp",
                                            "est. error 5.0% (noise 1.8%, bias 4.7%)", "radius 0.0185"};
    // 700 pixels hold 100 characters: the first four parts (86), then the radius whole.
    EXPECT_EQ(lines_of_parts(parts, "  |  ", 700.0f, measure),
              (std::vector<std::string>{"16 of 16 passes  |  320M photons  |  16 spp  |  est. error 5.0% (noise 1.8%, bias 4.7%)",
                                        "radius 0.0185"}));
    // Wide enough for all: one line, as refinement_summary joins them.
    EXPECT_EQ(lines_of_parts(parts, "  |  ", 1e4f, measure).size(), 1u);
    // Narrower than any part: one part a line, none cut.
    EXPECT_EQ(lines_of_parts(parts, "  |  ", 10.0f, measure), parts);
    EXPECT_TRUE(lines_of_parts({}, "  |  ", 100.0f, measure).empty());
}

}  // namespace
}  // namespace caustica::ui
