// Animations of `caustica render` (docs/ANIMATION.md): --frames and --orbit-frames parsed and
// refused with clear messages, the frames and files they make, orbit cameras (frame 1 is the
// script's camera bit for bit, the others turned about up around the target), and one run of the
// binary.
#include "app/animation.h"
#include "core/io/png_io.h"
#include "core/scene/orbit_camera.h"
#include "core/scene/source_location.h"
#include "tests/temp_folder.h"

#include "tests/run_command.h"

#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sys/wait.h>

namespace caustica {
namespace {

using testing::TempFolder;

std::string error_of(std::vector<std::string> tokens) {
    try {
        take_animation_arguments(tokens);
    } catch (const InputError& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(AnimationArguments, TakesBothFormsAndLeavesTheRest) {
    std::vector<std::string> tokens = {"--frames", "2:5", "scene.lua", "--orbit-frames=30", "-q", "draft"};
    AnimationRequest r = take_animation_arguments(tokens);
    EXPECT_EQ(r.first, 2);
    EXPECT_EQ(r.last, 5);
    EXPECT_EQ(r.orbit_frames, 30);
    EXPECT_TRUE(r.any());
    EXPECT_EQ(tokens, (std::vector<std::string>{"scene.lua", "-q", "draft"}));

    tokens = {"--frames=7", "--orbit-frames", "100000", "x.lua"};
    r = take_animation_arguments(tokens);
    EXPECT_EQ(r.first, 7);
    EXPECT_EQ(r.last, 7);
    EXPECT_EQ(r.frames_text, "--frames 7");
    EXPECT_EQ(r.orbit_frames, max_animation_frames);
    EXPECT_EQ(tokens, std::vector<std::string>{"x.lua"});

    tokens = {"x.lua", "--frames", "3"};
    r = take_animation_arguments(tokens);
    EXPECT_EQ(r.first, 3);
    EXPECT_EQ(r.last, 3);
    EXPECT_FALSE(r.orbit());

    tokens = {"x.lua", "-o", "a.png"};
    r = take_animation_arguments(tokens);
    EXPECT_FALSE(r.any());
    EXPECT_EQ(tokens.size(), 3u);
}

TEST(AnimationArguments, BadValuesAreRefusedWithTheirText) {
    EXPECT_EQ(error_of({"--frames", "5:2"}), "--frames 5:2: the first frame (5) is after the last (2)");
    EXPECT_EQ(error_of({"--frames", "0:3"}), "--frames 0:3: frames are numbered from 1");
    EXPECT_EQ(error_of({"--frames=0"}), "--frames 0: frames are numbered from 1");
    EXPECT_EQ(error_of({"--frames", "-2"}), "--frames -2: frames are numbered from 1 (no negative numbers)");
    EXPECT_EQ(error_of({"--frames", "a:b"}),
              "--frames a:b: 'a' is not a whole number (expects A:B (frames A to B, numbered from 1) or N (frame N alone))");
    EXPECT_EQ(error_of({"--frames", "2:"}),
              "--frames 2:: expects A:B (frames A to B, numbered from 1) or N (frame N alone)");
    EXPECT_EQ(error_of({"--frames", ":4"}),
              "--frames :4: expects A:B (frames A to B, numbered from 1) or N (frame N alone)");
    EXPECT_EQ(error_of({"--frames", "1.5"}),
              "--frames 1.5: '1.5' is not a whole number (expects A:B (frames A to B, numbered from 1) or N (frame N alone))");
    EXPECT_EQ(error_of({"--frames"}), "--frames: expects A:B (frames A to B, numbered from 1) or N (frame N alone)");
    EXPECT_EQ(error_of({"--orbit-frames"}), "--orbit-frames: expects a number of frames");
    EXPECT_EQ(error_of({"--orbit-frames="}), "--orbit-frames: expects a number of frames");
    EXPECT_EQ(error_of({"--frames="}), "--frames: expects A:B (frames A to B, numbered from 1) or N (frame N alone)");
    EXPECT_EQ(error_of({"--frames", "2:-1"}), "--frames 2:-1: frames are numbered from 1 (no negative numbers)");
    EXPECT_EQ(error_of({"--orbit-frames", "0"}), "--orbit-frames 0: expects a number of frames from 1 to 100000");
    EXPECT_EQ(error_of({"--orbit-frames=-3"}), "--orbit-frames -3: expects a number of frames from 1 to 100000");
    EXPECT_EQ(error_of({"--orbit-frames", "100001"}), "--orbit-frames 100001: at most 100000 frames");
    EXPECT_EQ(error_of({"--orbit-frames", "99999999999999999999999"}),
              "--orbit-frames 99999999999999999999999: at most 100000 frames");
    EXPECT_EQ(error_of({"--orbit-frames", "+3"}), "--orbit-frames +3: '+3' is not a whole number (expects a number of frames)");
    EXPECT_EQ(error_of({"--orbit-frames", " 3"}), "--orbit-frames  3: ' 3' is not a whole number (expects a number of frames)");
}

RenderJob job(const std::string& output, int line) {
    RenderJob j;
    j.output = output;
    j.width = 40;
    j.height = 30;
    j.where = SourceLocation{"scene.lua", line};
    j.camera.eye = {1.0, 2.0, 7.0};
    j.camera.view = {-0.1, -0.2, -1.0};
    j.camera.up = {0.0, 1.0, 0.0};
    j.camera.fovy_degrees = 40.0;
    return j;
}

AnimationRequest request(std::vector<std::string> tokens) { return take_animation_arguments(tokens); }

std::vector<std::string> paths(const AnimationPlan& plan) {
    std::vector<std::string> p;
    for (const AnimationFrame& f : plan.frames) p.push_back(f.path);
    return p;
}

std::string plan_error(const AnimationRequest& r, const std::vector<RenderJob>& jobs) {
    try {
        plan_animation(r, jobs, "");
    } catch (const InputError& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(AnimationPlan, ScriptFramesKeepTodaysNamesAndFramesPicksThem) {
    const std::vector<RenderJob> jobs = {job("a.png", 3), job("img/b.png", 4), job("c.exr", 5)};
    AnimationPlan all = plan_animation({}, jobs, "");
    EXPECT_EQ(paths(all), (std::vector<std::string>{"a.png", "img/b.png", "c.exr"}));
    EXPECT_FALSE(all.needs_target);
    EXPECT_TRUE(all.warnings.empty());
    EXPECT_EQ(paths(plan_animation({}, jobs, "out/x.png")),
              (std::vector<std::string>{"out/x-1.png", "out/x-2.png", "out/x-3.png"}));
    EXPECT_EQ(paths(plan_animation({}, {jobs[0]}, "out/x.png")), std::vector<std::string>{"out/x.png"});

    const AnimationPlan picked = plan_animation(request({"--frames", "2:3"}), jobs, "x.png");
    ASSERT_EQ(picked.frames.size(), 2u);
    EXPECT_EQ(paths(picked), (std::vector<std::string>{"x-2.png", "x-3.png"}));
    EXPECT_EQ(picked.frames[0].number, 2);
    EXPECT_EQ(picked.frames[0].job_index, 1);
    EXPECT_EQ(picked.frames[1].job.where.line, 5);
    EXPECT_EQ(frame_label(picked.frames[1]), "3/3");
    EXPECT_EQ(picked.frames[0].job.camera.eye, jobs[1].camera.eye);
    // One frame of a single gr.render with -o keeps the name -o gives it.
    EXPECT_EQ(paths(plan_animation(request({"--frames", "1"}), {jobs[0]}, "y.png")), std::vector<std::string>{"y.png"});

    EXPECT_EQ(plan_error(request({"--frames", "2:4"}), jobs), "--frames 2:4: the script's gr.render calls are frames 1:3");
    EXPECT_EQ(plan_error(request({"--frames", "2"}), {jobs[0]}), "--frames 2: the script's gr.render calls are frames 1:1");
    EXPECT_EQ(plan_error(request({"--frames", "4:6", "--orbit-frames", "5"}), jobs),
              "--frames 4:6: --orbit-frames 5 makes frames 1:5");
}

TEST(AnimationPlan, OrbitFramesAreNumberedFromTheOutputOrTheScriptsName) {
    const std::vector<RenderJob> one = {job("img/scene.png", 3)};
    AnimationPlan plan = plan_animation(request({"--orbit-frames", "3"}), one, "");
    EXPECT_EQ(paths(plan), (std::vector<std::string>{"img/scene-0001.png", "img/scene-0002.png", "img/scene-0003.png"}));
    EXPECT_TRUE(plan.needs_target);
    EXPECT_TRUE(plan.warnings.empty());
    EXPECT_EQ(frame_label(plan.frames[2]), "3/3");

    plan = plan_animation(request({"--orbit-frames", "12345", "--frames", "9999:10001"}), one, "o/x.exr");
    EXPECT_EQ(paths(plan), (std::vector<std::string>{"o/x-09999.exr", "o/x-10000.exr", "o/x-10001.exr"}));
    EXPECT_EQ(plan.frames[0].number, 9999);
    EXPECT_EQ(frame_label(plan.frames[1]), "10000/12345");

    const std::vector<RenderJob> two = {job("a.png", 7), job("b.png", 9)};
    plan = plan_animation(request({"--orbit-frames=2"}), two, "");
    EXPECT_EQ(paths(plan), (std::vector<std::string>{"a-0001.png", "a-0002.png"}));
    EXPECT_EQ(plan.warnings,
              std::vector<std::string>{"--orbit-frames: the script calls gr.render 2 times; only the first (scene.lua:7) is orbited"});
    for (const AnimationFrame& f : plan.frames) EXPECT_EQ(f.job.where.line, 7);

    EXPECT_EQ(numbered_frame_path("x.png", 12, 999), "x-0012.png");
    EXPECT_EQ(numbered_frame_path("a.b/x.y.pfm", 3, 1000000), "a.b/x.y-0000003.pfm");
}

void expect_near(const glm::dvec3& a, const glm::dvec3& b, double tolerance = 1e-9) {
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

bool same_bits(const CameraDesc& a, const CameraDesc& b) {
    return std::memcmp(&a.eye, &b.eye, sizeof a.eye) == 0 && std::memcmp(&a.view, &b.view, sizeof a.view) == 0 &&
           std::memcmp(&a.up, &b.up, sizeof a.up) == 0 && std::memcmp(&a.fovy_degrees, &b.fovy_degrees, sizeof(double)) == 0;
}

TEST(AnimationOrbit, TurnsAboutUpAroundTheTargetAndComesBack) {
    CameraDesc script = job("x.png", 1).camera;
    script.up = {0.3, 1.0, 0.1};  // not perpendicular to the view, not unit: the orbit turns about it all the same
    script.view = {-0.1, -0.2, -2.0};  // not unit either
    const double distance = 6.5;
    const glm::dvec3 up = glm::normalize(script.up);
    const glm::dvec3 target = script.eye + glm::normalize(script.view) * distance;
    const glm::dvec3 start = script.eye - target;
    const glm::dvec3 right = glm::normalize(glm::cross(script.view, script.up));
    const int n = 7;
    EXPECT_TRUE(same_bits(orbit_frame_camera(script, distance, 1, n), script));
    for (int i = 2; i <= n + 1; ++i) {
        const CameraDesc c = orbit_frame_camera(script, distance, i, n);
        const glm::dvec3 offset = c.eye - target;
        EXPECT_NEAR(glm::length(offset), distance, 1e-9) << i;
        EXPECT_NEAR(glm::dot(offset, up), glm::dot(start, up), 1e-9) << i;  // turned about up only
        expect_near(glm::normalize(c.view), -offset / distance);         // looking at the target
        expect_near(c.up, up);
        EXPECT_EQ(c.fovy_degrees, script.fovy_degrees);
        // The angle turned, in the plane across up, with its sign: towards the camera's right first.
        const glm::dvec3 a = start - glm::dot(start, up) * up, b = offset - glm::dot(offset, up) * up;
        const double angle = std::atan2(glm::dot(glm::cross(a, b), up), glm::dot(a, b));
        const double wanted = 2.0 * glm::pi<double>() * (i - 1) / n;
        EXPECT_NEAR(std::remainder(angle - wanted, 2.0 * glm::pi<double>()), 0.0, 1e-9) << i;
        if (i == 2) {
            EXPECT_GT(glm::dot(c.eye - script.eye, right), 0.0);
        }
    }
    // Frame N + 1 would be frame 1 again: the orbit closes.
    const CameraDesc back = orbit_frame_camera(script, distance, n + 1, n);
    expect_near(back.eye, script.eye);
    expect_near(back.view, glm::normalize(script.view));
}

TEST(AnimationOrbit, TargetFromTheCallbackOrTheDefaultRule) {
    RenderJob j = job("s.png", 2);
    j.camera.eye = {0.0, 0.0, 5.0};
    j.camera.view = {0.0, 0.0, -1.0};
    int calls = 0;
    const auto hit_at_4 = [&](const RenderJob& asked) {
        ++calls;
        EXPECT_EQ(asked.where.line, 2);
        return 4.0;  // a sphere of radius 1 at the origin
    };
    AnimationPlan plan = plan_frames(request({"--orbit-frames", "4"}), {j, job("t.png", 3)}, "", hit_at_4);
    EXPECT_EQ(calls, 1);
    EXPECT_FALSE(plan.needs_target);
    ASSERT_EQ(plan.frames.size(), 4u);
    EXPECT_TRUE(same_bits(plan.frames[0].job.camera, j.camera));
    expect_near(plan.frames[1].job.camera.eye, {4.0, 0.0, 1.0});  // a quarter turn to the right around (0, 0, 1)
    expect_near(plan.frames[1].job.camera.view, {-1.0, 0.0, 0.0});
    expect_near(plan.frames[2].job.camera.eye, {0.0, 0.0, -3.0});
    expect_near(plan.frames[3].job.camera.eye, {-4.0, 0.0, 1.0});

    // A view ray that hits nothing: the point of the view axis nearest the origin.
    plan = plan_frames(request({"--orbit-frames", "4", "--frames", "3"}), {j}, "", [](const RenderJob&) { return 0.0; });
    ASSERT_EQ(plan.frames.size(), 1u);
    EXPECT_EQ(plan.frames[0].path, "s-0003.png");
    expect_near(plan.frames[0].job.camera.eye, {0.0, 0.0, -5.0});

    // Script frames never ask for a target.
    plan = plan_frames({}, {j}, "", [&](const RenderJob&) { ++calls; return 1.0; });
    EXPECT_EQ(calls, 1);
    EXPECT_TRUE(same_bits(plan.frames[0].job.camera, j.camera));
}

struct CliRun {
    int code = -1;
    std::string output;
};

CliRun run_caustica(const TempFolder& folder, const std::string& args) {
    const caustica::testing::CommandResult r =
        caustica::testing::run_shell("cd '" + folder.path().string() + "' && '" CAUSTICA_BINARY "' " + args);
    return {r.code, r.output};
}

std::string text_of(const Png8& png, const std::string& key) {
    for (const auto& [k, v] : png.text)
        if (k == key) return v;
    return "(missing)";
}

TEST(AnimationCli, OrbitAndPickedFramesThroughTheBinary) {
    const TempFolder folder("caustica_animation");
    folder.write("scene.lua",
                 "m = gr.material({0.8, 0.2, 0.2}, {0.3, 0.3, 0.3}, 20)\n"
                 "g = gr.material({0.2, 0.7, 0.3}, {0, 0, 0}, 0)\n"
                 "root = gr.node('root')\n"
                 "s = gr.nh_sphere('s', {0, 0, 0}, 1)\n"
                 "s:set_material(m)\n"
                 "root:add_child(s)\n"
                 "b = gr.nh_box('b', {1.2, -1, -0.5}, 1)\n"
                 "b:set_material(g)\n"
                 "root:add_child(b)\n"
                 "l = gr.light({5, 5, 5}, {1, 1, 1}, {1, 0, 0})\n"
                 "gr.render(root, 'out.png', 32, 32, {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 50, {0.1, 0.1, 0.1}, {l})\n");
    const std::string common = "render scene.lua --silent --reproducible ";
    ASSERT_EQ(run_caustica(folder, common + "-o plain.png").code, 0);
    const CliRun orbit = run_caustica(folder, common + "--orbit-frames 3 -o orbit.png");
    ASSERT_EQ(orbit.code, 0) << orbit.output;
    const Png8 plain = read_png(folder.file("plain.png"));
    const Png8 f1 = read_png(folder.file("orbit-0001.png")), f2 = read_png(folder.file("orbit-0002.png")),
               f3 = read_png(folder.file("orbit-0003.png"));
    EXPECT_EQ(f1.data, plain.data);  // frame 1 is the script's camera exactly
    EXPECT_NE(f2.data, plain.data);
    EXPECT_NE(f3.data, f2.data);
    EXPECT_EQ(text_of(plain, "caustica:frame"), "(missing)");
    EXPECT_EQ(text_of(f2, "caustica:frame"), "2/3");
    EXPECT_EQ(text_of(f1, "caustica:camera"), text_of(plain, "caustica:camera"));
    // A third of a turn around the orbit target: on the view axis at the depth d of what the camera
    // sees (docs/ANIMATION.md), here within the sphere (its front 4 away, its back 6), so the eye is
    // (0, 0, 5 - d) + d (sin 120, 0, cos 120) and looks back at it.
    glm::dvec3 eye, view;
    ASSERT_EQ(std::sscanf(text_of(f2, "caustica:camera").c_str(), "eye %lf %lf %lf view %lf %lf %lf", &eye.x, &eye.y,
                          &eye.z, &view.x, &view.y, &view.z),
              6);
    const double d = eye.x / (0.5 * std::sqrt(3.0));
    EXPECT_GT(d, 4.0);
    EXPECT_LT(d, 6.0);
    expect_near(eye, {0.5 * std::sqrt(3.0) * d, 0.0, 5.0 - 1.5 * d}, 1e-5);
    expect_near(view, {-0.5 * std::sqrt(3.0), 0.0, 0.5}, 1e-6);

    // --frames outside the orbit: refused before anything is written, naming the range.
    const CliRun bad = run_caustica(folder, common + "--orbit-frames 3 --frames 3:4 -o late.png");
    EXPECT_EQ(bad.code, 2);
    EXPECT_NE(bad.output.find("--frames 3:4: --orbit-frames 3 makes frames 1:3"), std::string::npos) << bad.output;
    EXPECT_FALSE(std::filesystem::exists(folder.file("late-0003.png")));

    // --frames without an orbit picks gr.render calls: the second of two, named as without --frames.
    std::string two;
    {
        std::ifstream in(folder.file("scene.lua"));
        two.assign(std::istreambuf_iterator<char>(in), {});
    }
    folder.write("two.lua", two + "gr.render(root, 'second.png', 20, 10, {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 50, {0, 0, 0}, {l})\n");
    const CliRun second = run_caustica(folder, "render two.lua --silent --frames 2 -o pick.png");
    ASSERT_EQ(second.code, 0) << second.output;
    EXPECT_FALSE(std::filesystem::exists(folder.file("pick-1.png")));
    const Png8 picked = read_png(folder.file("pick-2.png"));
    EXPECT_EQ(picked.width, 20);
    EXPECT_EQ(text_of(picked, "caustica:frame"), "2/2");
}

}  // namespace
}  // namespace caustica
