// The preview's responsiveness (docs/PERFORMANCE.md, "The preview"), measured headless:
//  - latency from a camera change to the first coarse preview and to the first full-resolution
//    pass at 1280 x 720 on scenes/default.lua, the renderer alone, busy with the previous view
//    when the camera moves, as while dragging;
//  - the same end to end through the UI (target: p90 under 50 ms): a mouse drag in, the frame
//    showing the new view's coarse preview drawn, with where the time went;
//  - the UI thread's frame time while rendering (target 60 fps, never below 30), with the real
//    panels drawn by OSMesa, while the camera orbits every frame and while a long render runs.
// usage: bench_preview [SCENE.lua] [--changes N] [--frames N] [--size WxH (of the first measurement)]
//          [--ui-latency (only the drag through the UI)] [--fixed-beat (frames on a fixed 60 Hz beat)]
//          [--compare-pacing (both pacings, alternating)] [--draw-profile (where an idle frame's time goes)]
//          [--draw-variants [--fragment FILE] (the image's draw cost by texture format and shader)]
//          [--drag (a continuous drag, both pacings, --frames frames)]
//          [--launch [--changes N] (opening the scene to its first image, classic and progressive)]
#include "ui/frame_pacing.h"
#include "ui/headless_window.h"
#include "ui/preview_driver.h"
#include "ui/shader_sources.h"
#include "ui/view_main.h"

#include "core/lua/scene_loader.h"
#include "core/scene/orbit_camera.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <iterator>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>
#include <sys/resource.h>

namespace {

using namespace caustica;
using namespace caustica::ui;
using clock_type = std::chrono::steady_clock;

double ms_since(clock_type::time_point t0) {
    return std::chrono::duration<double, std::milli>(clock_type::now() - t0).count();
}

struct Summary {
    double median, p90, worst, mean;
};

Summary summarise(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    double sum = 0.0;
    for (double x : v) sum += x;
    auto at = [&](double q) { return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))]; };
    return {at(0.5), at(0.9), v.back(), sum / v.size()};
}

void row(const char* what, const Summary& s, const char* unit, const char* target) {
    std::printf("  %-46s %8.2f %8.2f %8.2f %s   %s\n", what, s.median, s.p90, s.worst, unit, target);
}

/// Camera change -> first coarse preview shown, and -> first full pass shown, at 1280 x 720.
void latency(const RenderJob& script_job, int changes, int width, int height) {
    RenderJob job = script_job;
    job.width = width;
    job.height = height;
    PreviewDriver driver;
    driver.request(job);
    while (!driver.finished()) {  // the BVH and the photons: built once, before the camera moves
        driver.update();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    const RenderSession::StageCounters built = driver.session().stage_counters();
    OrbitCamera orbit(job.camera, default_target_distance(job.camera));
    std::vector<double> preview, full, restart;
    for (int i = 0; i < changes; ++i) {
        orbit.orbit(2.0, 0.3);
        job.camera = orbit.desc();
        const std::uint64_t restarts = driver.restarts();
        const auto t0 = clock_type::now();
        driver.request(job);
        double preview_ms = -1.0;
        for (;;) {  // the UI's frame loop, polled every 0.2 ms to time the moments precisely
            driver.update();
            const SessionProgress& p = driver.progress();
            const std::size_t per_pass = p.passes ? p.tiles_total / p.passes : 0;
            if (driver.restarts() > restarts && per_pass > 0) {
                if (preview_ms < 0.0 && p.tiles_done >= per_pass) preview_ms = ms_since(t0);
                if (driver.first_full_pass_done()) break;
            }
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        full.push_back(ms_since(t0));
        preview.push_back(preview_ms);
        restart.push_back(1e3 * driver.last_restart_seconds());
        // Let the anti-aliasing pass run a little, so that the next change interrupts it.
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        driver.update();
    }
    const RenderSession::StageCounters after = driver.session().stage_counters();
    std::printf("\ncamera change at %d x %d (%d changes; %d scene builds and %d photon passes after the first)\n", width,
                height, changes, after.scene_builds - built.scene_builds, after.photon_passes - built.photon_passes);
    std::printf("  %-46s %8s %8s %8s\n", "", "median", "p90", "max");
    row("to the first coarse preview (8 x 8 blocks)", summarise(preview), "ms", "target < 50 ms");
    row("to the first full-resolution pass", summarise(full), "ms", "");
    row("restart: set_job + start on the UI thread", summarise(restart), "ms", "");
    std::printf("  %-46s %8.1f ms (the first render allocates the image)\n", "longest restart of the run",
                1e3 * driver.longest_restart_seconds());
}

/// The whole preview in a 1280 x 720 headless window, a scene open at a resolution scale: what
/// every UI measurement below starts from.
struct PreviewUnderTest {
    PreviewUnderTest(const std::string& scene, double resolution_scale) {
        model.open(scene);
        model.set_resolution_scale(resolution_scale);
    }
    /// Runs frames (2 ms apart, as the waits poll) until `done`.
    template <typename Done>
    void frames_until(Done&& done, const HeadlessInput& input = {}) {
        while (!done()) {
            window.frame(app, input);
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
    }
    /// Until the render is finished and no change waits.
    void settle(const HeadlessInput& input = {}) {
        frames_until([&] { return model.driver().finished() && !model.changes_pending(); }, input);
    }

    HeadlessWindow window{1280, 720};
    ViewModel model{ModelConfig{}};
    ViewApp app{model};
};

/// The same through the whole UI, end to end: a mouse drag goes in as the platform's input, frames
/// run with the panels drawn, paced as the app paces them (ui/frame_pacing.h) or, for comparison,
/// on a fixed 60 Hz beat, and the time is taken when a frame showing the whole coarse preview has
/// been drawn (glFinish). The drag moves again 100 ms after that, while the full-resolution pass
/// runs. 960 x 960: as many pixels as 1280 x 720, from the script's square 512 x 512. Where the
/// time goes: how long the frame reading the drag took (the render restarts within it) and when the
/// session had the coarse pass complete (sampled every 0.5 ms between frames, as the wait polls).
/// With both pacings, the changes alternate between them, so that both see the same machine load.
void latency_with_ui(const std::string& scene, int changes, bool new_pacing, bool fixed_beat) {
    PreviewUnderTest preview(scene, 960.0 / 512.0);
    HeadlessWindow& window = preview.window;
    ViewModel& model = preview.model;
    ViewApp& app = preview.app;
    HeadlessInput input;
    input.mouse = glm::vec2(300.0f, 360.0f);  // over the image, left of the sidebar
    preview.settle(input);
    input.buttons[0] = true;  // the drag begins: held from here on
    window.frame(app, input);
    struct Times {
        std::vector<double> preview, read_frame, ready, build, draw;
    } times[2];  // [fixed beat, frame_pacing.h]
    for (int i = 0; i < changes; ++i) {
        const bool fixed = fixed_beat && (!new_pacing || i % 2 == 0);
        const std::uint64_t restarts = model.driver().restarts();
        double preview_ms = -1.0, ready_ms = -1.0;
        const auto t0 = clock_type::now();
        auto sample = [&] {
            const PreviewDriver& driver = model.driver();
            if (driver.restarts() <= restarts || ready_ms >= 0.0) return;
            const SessionProgress p = driver.session().progress();
            const std::size_t per_pass = p.passes ? p.tiles_total / p.passes : 0;
            if (p.generation == driver.generation() && per_pass > 0 && p.tiles_done >= per_pass) ready_ms = ms_since(t0);
        };
        input.mouse.x += (i % 20 < 10 ? 7.0f : -7.0f);  // 2.1 degrees of orbit, to and fro
        auto next = t0;
        Times& t = times[fixed ? 0 : 1];
        window.skip_undrawable_frames(&model, !fixed);
        for (int frames = 0;; ++frames) {
            const auto frame_start = clock_type::now();
            window.frame(app, input);
            if (frames == 0) t.read_frame.push_back(ms_since(t0));
            sample();
            const PreviewDriver& driver = model.driver();
            const SessionProgress& p = driver.progress();
            const std::size_t per_pass = p.passes ? p.tiles_total / p.passes : 0;
            if (preview_ms < 0.0 && driver.restarts() > restarts && per_pass > 0 && p.tiles_done >= per_pass) {
                preview_ms = ms_since(t0);
                t.build.push_back(window.last_frame_times().build);
                t.draw.push_back(window.last_frame_times().draw);
            }
            if (preview_ms >= 0.0 && ms_since(t0) > preview_ms + 100.0) break;
            if (fixed) {  // wait_for_frame on a fixed beat, sampled
                next += std::chrono::microseconds(16667);
                if (next < clock_type::now()) next = clock_type::now();
                for (;;) {
                    model.poll();
                    sample();
                    const auto now = clock_type::now();
                    if (now >= next) break;
                    std::this_thread::sleep_for(std::min<clock_type::duration>(next - now, std::chrono::microseconds(500)));
                }
            } else {
                wait_for_next_frame(model, frame_start, FramePacing{}, sample);
            }
        }
        t.preview.push_back(preview_ms);
        t.ready.push_back(ready_ms);
    }
    for (int k = 0; k < 2; ++k) {
        const Times& t = times[k];
        if (t.preview.empty()) continue;
        std::printf("\nthe same through the UI: a mouse drag, 960 x 960 render, %s (%zu changes)\n",
                    k == 0 ? "fixed 60 Hz beat" : "frames paced by ui/frame_pacing.h", t.preview.size());
        std::printf("  %-46s %8s %8s %8s\n", "", "median", "p90", "max");
        row("to the frame showing the coarse preview", summarise(t.preview), "ms", "target < 50 ms");
        row("  the frame reading the drag (drawn)", summarise(t.read_frame), "ms", "");
        row("  drag -> coarse pass complete in the session", summarise(t.ready), "ms", "");
        row("  the frame showing it: build (upload, panels)", summarise(t.build), "ms", "");
        row("  the frame showing it: draw, until glFinish", summarise(t.draw), "ms", "");
    }
}

/// A continuous drag (--drag): the mouse moves 3 pixels (0.9 degrees) before every frame for
/// `frames` frames, in blocks of 40 frames alternating between the two pacings. For every view
/// shown (a frame drawing the complete coarse preview of a render not shown before): the time from
/// the start of the frame that read the drag that render shows to the end of the frame showing
/// it, and the time between such frames.
void continuous_drag(const std::string& scene, int frames) {
    PreviewUnderTest preview(scene, 960.0 / 512.0);
    HeadlessWindow& window = preview.window;
    ViewModel& model = preview.model;
    ViewApp& app = preview.app;
    HeadlessInput input;
    input.mouse = glm::vec2(300.0f, 360.0f);
    preview.settle(input);
    input.buttons[0] = true;
    window.frame(app, input);
    struct Times {
        std::vector<double> latency, interval;
        int frames = 0, drawn = 0;
    } times[2];
    std::uint64_t shown_generation = model.driver().generation();
    clock_type::time_point last_shown{}, last_read{};
    std::vector<std::pair<std::uint64_t, clock_type::time_point>> read_at;  // generation -> frame that read its drag
    std::map<std::uint64_t, std::size_t> uploaded;  // generation -> tiles uploaded
    auto next = clock_type::now();
    for (int i = 0; i < frames; ++i) {
        const bool fixed = (i / 40) % 2 == 0;
        Times& t = times[fixed ? 0 : 1];
        window.skip_undrawable_frames(&model, !fixed);
        input.mouse.x += (i / 100) % 2 == 0 ? 3.0f : -3.0f;
        const auto frame_start = clock_type::now();
        last_read = frame_start;
        auto note_restart = [&] {
            const std::uint64_t g = model.driver().generation();
            if (read_at.empty() || read_at.back().first != g) read_at.emplace_back(g, last_read);
        };
        window.frame(app, input);
        ++t.frames;
        t.drawn += window.last_frame_drawn();
        // Tiles uploaded by render (a tile's coarse block and later its full pass count twice, but
        // the coarse pass covers every tile before the next pass starts).
        for (std::uint64_t g : model.driver().changed_generations()) ++uploaded[g];
        note_restart();
        std::uint64_t newest = 0;
        for (const auto& [g, n] : uploaded)
            if (g > shown_generation && n >= model.driver().tiles().size()) newest = std::max(newest, g);
        if (window.last_frame_drawn() && newest > 0) {
            shown_generation = newest;
            const auto now = clock_type::now();
            for (const auto& [g, at] : read_at)
                if (g == newest) t.latency.push_back(std::chrono::duration<double, std::milli>(now - at).count());
            if (last_shown != clock_type::time_point{})
                t.interval.push_back(std::chrono::duration<double, std::milli>(now - last_shown).count());
            last_shown = now;
        }
        if (fixed) {
            next = std::max(next + std::chrono::microseconds(16667), clock_type::now());
            for (;;) {
                model.poll();
                note_restart();
                const auto now = clock_type::now();
                if (now >= next) break;
                std::this_thread::sleep_for(std::min<clock_type::duration>(next - now, std::chrono::microseconds(500)));
            }
        } else {
            wait_for_next_frame(model, frame_start, FramePacing{}, note_restart);
            next = clock_type::now();
        }
    }
    for (int k = 0; k < 2; ++k) {
        const Times& t = times[k];
        if (t.latency.empty() || t.interval.empty()) continue;
        std::printf("\na continuous drag, 960 x 960 render, %s (%d frames, %d drawn, %zu views shown)\n",
                    k == 0 ? "fixed 60 Hz beat" : "frames paced by ui/frame_pacing.h", t.frames, t.drawn,
                    t.latency.size());
        std::printf("  %-46s %8s %8s %8s\n", "", "median", "p90", "max");
        row("drag read -> its view's coarse preview shown", summarise(t.latency), "ms", "");
        row("between two views shown", summarise(t.interval), "ms", "");
    }
}

/// Where an idle frame's time goes (render finished, 960 x 960 image, 1280 x 720 window).
void draw_profile(const std::string& scene, int frames) {
    PreviewUnderTest preview(scene, 960.0 / 512.0);
    HeadlessWindow& window = preview.window;
    ViewApp& app = preview.app;
    preview.settle();
    window.measure_draw(true);
    std::vector<double> build, image, panels;
    for (int i = 0; i < frames; ++i) {
        window.frame(app);
        build.push_back(window.last_frame_times().build);
        image.push_back(window.last_frame_times().draw_image);
        panels.push_back(window.last_frame_times().draw - window.last_frame_times().draw_image);
    }
    std::printf("\nan idle frame, 960 x 960 image in a 1280 x 720 window (%d frames)\n", frames);
    std::printf("  %-46s %8s %8s %8s\n", "", "median", "p90", "max");
    row("build (input, model, upload, panels' layout)", summarise(build), "ms", "");
    row("draw the image and overlay (glFinish)", summarise(image), "ms", "");
    row("draw ImGui's panels (glFinish)", summarise(panels), "ms", "");
}

/// What drawing the image costs in llvmpipe by texture format and shader (--draw-variants): a
/// 960 x 960 texture drawn into the 910 x 720 image area (scale 0.75, filtered), as ViewApp does.
void draw_variants(int frames, const std::string& fragment_file) {
    HeadlessWindow window(1280, 720);
    auto compile = [](GLenum type, const char* text) {
        const GLuint shader = glCreateShader(type);
        glShaderSource(shader, 1, &text, nullptr);
        glCompileShader(shader);
        return shader;
    };
    const char* vertex = R"(#version 330 core
out vec2 v_uv;
void main() {
    vec2 corner = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
    v_uv = corner;
    vec2 p = vec2(910.0, 720.0) * corner / vec2(1280.0, 720.0);
    gl_Position = vec4(p.x * 2.0 - 1.0, 1.0 - p.y * 2.0, 0.0, 1.0);
})";
    const char* plain = R"(#version 330 core
uniform sampler2D u_image; uniform float u_exposure; in vec2 v_uv; out vec4 out_colour;
void main() { vec3 c = clamp(texture(u_image, v_uv).rgb * u_exposure, 0.0, 1.0); out_colour = vec4(floor(c * 255.0) / 255.0, 1.0); })";
    const char* srgb = R"(#version 330 core
uniform sampler2D u_image; uniform float u_exposure; in vec2 v_uv; out vec4 out_colour;
void main() { vec3 c = clamp(texture(u_image, v_uv).rgb * u_exposure, 0.0, 1.0);
  c = mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c)); out_colour = vec4(c, 1.0); })";
    const std::string image_frag(shader_source("image.frag"));  // u_mode 0, u_whole_pixels false
    std::string other;  // --fragment FILE: a candidate image.frag (its uniforms left at 0)
    if (!fragment_file.empty()) {
        std::ifstream in(fragment_file);
        if (!in) throw std::runtime_error(fragment_file + ": cannot read");
        other.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    struct Variant {
        const char* what;
        GLenum internal;
        GLenum filter;
        const char* fragment;
    };
    std::vector<Variant> variants = {
        {"RGB32F, linear, shaders/image.frag (as now)", GL_RGB32F, GL_LINEAR, image_frag.c_str()},
        {"RGB32F, linear, clamp + x255 only", GL_RGB32F, GL_LINEAR, plain},
        {"RGB32F, linear, sRGB pow", GL_RGB32F, GL_LINEAR, srgb},
        {"RGB32F, nearest", GL_RGB32F, GL_NEAREST, plain},
        {"RGBA32F, linear", GL_RGBA32F, GL_LINEAR, plain},
        {"RGBA16F, linear", GL_RGBA16F, GL_LINEAR, plain},
        {"RGBA8, linear", GL_RGBA8, GL_LINEAR, plain},
    };
    if (!other.empty()) variants.push_back({"RGB32F, linear, --fragment FILE", GL_RGB32F, GL_LINEAR, other.c_str()});
    std::vector<float> pixels(960 * 960 * 3);
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<float>(i % 977) / 977.0f;
    GLuint vao = 0, texture = 0;
    glGenVertexArrays(1, &vao);
    glGenTextures(1, &texture);
    std::printf("\ndrawing a 960 x 960 image into 910 x 720 pixels (llvmpipe, glFinish; %d frames)\n", frames);
    std::printf("  %-46s %8s %8s %8s\n", "", "median", "p90", "max");
    for (const Variant& v : variants) {
        const GLuint program = glCreateProgram(), vs = compile(GL_VERTEX_SHADER, vertex),
                     fs = compile(GL_FRAGMENT_SHADER, v.fragment);
        glAttachShader(program, vs);
        glAttachShader(program, fs);
        glLinkProgram(program);
        glDeleteShader(vs);
        glDeleteShader(fs);
        GLint linked = 0;
        glGetProgramiv(program, GL_LINK_STATUS, &linked);
        if (!linked) {
            std::printf("  %-46s does not compile or link\n", v.what);
            glDeleteProgram(program);
            continue;
        }
        glBindTexture(GL_TEXTURE_2D, texture);
        glTexImage2D(GL_TEXTURE_2D, 0, v.internal, 960, 960, 0, GL_RGB, GL_FLOAT, pixels.data());
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, v.filter);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, v.filter);
        glUseProgram(program);
        glUniform1i(glGetUniformLocation(program, "u_image"), 0);
        glUniform1f(glGetUniformLocation(program, "u_exposure"), 1.0f);
        glBindVertexArray(vao);
        std::vector<double> draw, upload;
        for (int i = 0; i < frames; ++i) {
            auto t0 = clock_type::now();
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 960, 960, GL_RGB, GL_FLOAT, pixels.data());
            glFinish();
            upload.push_back(ms_since(t0));
            t0 = clock_type::now();
            glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
            glFinish();
            draw.push_back(ms_since(t0));
        }
        row(v.what, summarise(draw), "ms", "draw");
        row("", summarise(upload), "ms", "upload of the whole image");
        glDeleteProgram(program);
    }
    glDeleteTextures(1, &texture);
    glDeleteVertexArrays(1, &vao);
}

/// CPU seconds used by the whole process so far (every thread: UI, llvmpipe, renderer).
double process_cpu_seconds() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

/// UI frame times with the whole window drawn, at 60 frames a second as the app paces them.
/// `wait_until_done`: measure an idle window (render finished) to get the UI's own CPU cost.
void frame_times(const std::string& scene, int frames, double resolution_scale, bool orbit, const char* what,
                 bool wait_until_done = false) {
    PreviewUnderTest preview(scene, resolution_scale);
    HeadlessWindow& window = preview.window;
    ViewModel& model = preview.model;
    ViewApp& app = preview.app;
    preview.frames_until([&] {  // loaded and rendered once
        return wait_until_done ? model.driver().finished() : model.driver().first_full_pass_done();
    });
    std::vector<double> times;
    const double cpu0 = process_cpu_seconds();
    int rendering = 0;
    auto next = clock_type::now();
    for (int i = 0; i < frames; ++i) {
        const auto t0 = clock_type::now();
        if (orbit) model.orbit(0.5, 0.0);
        window.frame(app);  // input, model, tile upload, panels, GL drawing, glFinish
        times.push_back(ms_since(t0));
        rendering += model.driver().busy();
        next += std::chrono::microseconds(16667);
        wait_for_frame(model, next);
    }
    const double cpu_ms = 1e3 * (process_cpu_seconds() - cpu0) / frames;
    const Summary s = summarise(times);
    std::printf("  %-46s %8.1f %8.1f %8.1f ms   %4.0f fps at p90, rendering in %3d%% of frames, %5.1f ms CPU/frame\n",
                what, s.median, s.p90, s.worst, 1000.0 / s.p90, 100 * rendering / frames, cpu_ms);
}

/// Opening a scene to its first image on screen (--launch), as when the preview starts: the window,
/// the model and the app are made, the scene opened, and frames run (paced as the app paces them)
/// until one has drawn the first complete pass of the render (the coarse preview, or the direct
/// light that classic shows while its photons are shot), then until the first full-resolution
/// pass. Classic and progressive alternate run by run, so that both see the same machine load.
void launch(const std::string& scene, int runs) {
    std::vector<double> first[2], full[2];
    const char* names[2] = {"classic", "progressive"};
    for (int i = 0; i < 2 * runs; ++i) {
        const int k = i % 2;
        const auto t0 = clock_type::now();
        HeadlessWindow window{1280, 720};
        ModelConfig config;
        config.option_tokens = {"--integrator", names[k]};
        ViewModel model{config};
        ViewApp app{model};
        model.open(scene);
        double first_ms = -1.0;
        for (;;) {
            const auto frame_start = clock_type::now();
            window.frame(app, HeadlessInput{});
            const PreviewDriver& driver = model.driver();
            const SessionProgress& p = driver.progress();
            const std::size_t per_pass = p.passes ? p.tiles_total / p.passes : 0;
            if (first_ms < 0.0 && driver.has_job() && per_pass > 0 && p.tiles_done >= per_pass) first_ms = ms_since(t0);
            if (driver.has_job() && driver.first_full_pass_done()) break;
            if (ms_since(t0) > 120e3) break;
            wait_for_next_frame(model, frame_start, FramePacing{}, [] {});
        }
        first[k].push_back(first_ms);
        full[k].push_back(ms_since(t0));
    }
    std::printf("\nopening %s to its first image, 1280 x 720 window (%d runs each, alternating)\n", scene.c_str(), runs);
    std::printf("  %-46s %8s %8s %8s\n", "", "median", "p90", "max");
    for (int k = 0; k < 2; ++k) {
        row((std::string(names[k]) + ": to the first image on screen").c_str(), summarise(first[k]), "ms", "");
        row((std::string(names[k]) + ": to the first full-resolution pass").c_str(), summarise(full[k]), "ms", "");
    }
}

}  // namespace

constexpr const char* usage =
    "usage: bench_preview [SCENE.lua] [--changes N] [--frames N] [--size WxH] [--ui-latency] [--fixed-beat]\n"
    "                     [--compare-pacing] [--draw-profile] [--draw-variants [--fragment FILE]] [--drag]\n"
    "                     [--launch]   (docs/PERFORMANCE.md, \"The preview\"; what each measures: the file's head)\n";

int main(int argc, char** argv) {
    std::string scene = CAUSTICA_SOURCE_DIR "/scenes/default.lua";
    int changes = 30, frames = 300, width = 1280, height = 720;
    bool ui_only = false, fixed_only = false, compare = false, profile = false, variants = false, drag = false,
         launching = false;
    std::string fragment_file;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--ui-latency")) ui_only = true;
        else if (!std::strcmp(argv[i], "--fixed-beat")) fixed_only = true;
        else if (!std::strcmp(argv[i], "--compare-pacing")) compare = true;
        else if (!std::strcmp(argv[i], "--draw-profile")) profile = true;
        else if (!std::strcmp(argv[i], "--draw-variants")) variants = true;
        else if (!std::strcmp(argv[i], "--drag")) drag = true;
        else if (!std::strcmp(argv[i], "--launch")) launching = true;
        else if (!std::strcmp(argv[i], "--fragment") && i + 1 < argc) fragment_file = argv[++i];
        else if (!std::strcmp(argv[i], "--changes") && i + 1 < argc) changes = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--size") && i + 1 < argc && std::sscanf(argv[i + 1], "%dx%d", &width, &height) == 2) ++i;
        else if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) frames = std::atoi(argv[++i]);
        else if (argv[i][0] == '-') {
            // --help, or an option it does not know (or one missing its value): the usage.
            const bool help = !std::strcmp(argv[i], "--help");
            std::fprintf(help ? stdout : stderr, "%s", usage);
            return help ? 0 : 2;
        } else scene = argv[i];
    }
    const SceneScript script = [&] {
        try {
            return load_scene_script(scene);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "bench_preview: %s\n", e.what());
            std::exit(1);
        }
    }();
    const RenderJob& job = script.renders.at(0);
    std::printf("bench_preview: %s, %u hardware threads, %lld photons\n", scene.c_str(), std::thread::hardware_concurrency(),
                job.options.caustic_num_photons);
    if (launching) {
        launch(scene, changes);
        return 0;
    }
    if (drag) {
        continuous_drag(scene, frames);
        return 0;
    }
    if (variants) {
        draw_variants(frames, fragment_file);
        return 0;
    }
    if (profile) {
        draw_profile(scene, frames);
        return 0;
    }
    if (!ui_only) latency(job, changes, width, height);
    latency_with_ui(scene, changes, !fixed_only, fixed_only || compare);
    if (ui_only) return 0;
    std::printf("\nUI frame time, 1280 x 720 window, panels drawn (OSMesa llvmpipe), paced at 60 fps\n");
    std::printf("  %-46s %8s %8s %8s\n", "", "median", "p90", "max");
    frame_times(scene, frames, 1.0, true, "orbiting every frame, 512 x 512 render");
    frame_times(scene, frames, 1280.0 / 512.0, true, "orbiting every frame, 1280 x 1280 render");
    frame_times(scene, frames, 2.0, false, "still camera, 1024 x 1024 render running");
    frame_times(scene, frames, 1.0, false, "idle: render finished (the UI's own cost)", true);
    return 0;
}
