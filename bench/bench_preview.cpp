// The preview's responsiveness (issue 5), measured headless:
//  - latency from a camera change to the first coarse preview and to the first full-resolution
//    pass at 1280 x 720 on scenes/default.lua (target: preview under 50 ms), the renderer
//    being busy with the previous view when the camera moves, as while dragging;
//  - the UI thread's frame time while rendering (target 60 fps, never below 30), with the real
//    panels drawn by OSMesa, while the camera orbits every frame and while a long render runs.
// usage: bench_preview [SCENE.lua] [--changes N] [--frames N] [--size WxH (of the first measurement)]
#include "ui/headless_window.h"
#include "ui/orbit_camera.h"
#include "ui/preview_driver.h"
#include "ui/view_main.h"

#include "core/lua/scene_loader.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
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

/// The same through the whole UI: the model orbits, frames run at 60 a second with the panels
/// drawn, and the time is taken when a frame shows the preview (960 x 960: as many pixels as
/// 1280 x 720, from the script's square 512 x 512).
void latency_with_ui(const std::string& scene, int changes) {
    HeadlessWindow window(1280, 720);
    ModelConfig config;
    ViewModel model(config);
    ViewApp app(model);
    model.open(scene);
    model.set_resolution_scale(960.0 / 512.0);
    while (!model.driver().finished() || model.changes_pending()) {
        window.frame(app);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    std::vector<double> preview, full;
    for (int i = 0; i < changes; ++i) {
        const std::uint64_t restarts = model.driver().restarts();
        const auto t0 = clock_type::now();
        model.orbit(2.0, 0.3);
        double preview_ms = -1.0;
        auto next = t0;
        for (;;) {
            window.frame(app);
            const PreviewDriver& driver = model.driver();
            const SessionProgress& p = driver.progress();
            const std::size_t per_pass = p.passes ? p.tiles_total / p.passes : 0;
            if (driver.restarts() > restarts && per_pass > 0) {
                if (preview_ms < 0.0 && p.tiles_done >= per_pass) preview_ms = ms_since(t0);
                if (driver.first_full_pass_done()) break;
            }
            next += std::chrono::microseconds(16667);
            wait_for_frame(model, next);
        }
        full.push_back(ms_since(t0));
        preview.push_back(preview_ms);
    }
    std::printf("\nthe same through the UI at 60 frames a second, 960 x 960 render (%d changes)\n", changes);
    std::printf("  %-46s %8s %8s %8s\n", "", "median", "p90", "max");
    row("to the frame showing the coarse preview", summarise(preview), "ms", "target < 50 ms");
    row("to the frame showing the first full pass", summarise(full), "ms", "");
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
    HeadlessWindow window(1280, 720);
    ModelConfig config;
    ViewModel model(config);
    ViewApp app(model);
    model.open(scene);
    model.set_resolution_scale(resolution_scale);
    while (!(wait_until_done ? model.driver().finished() : model.driver().first_full_pass_done())) {
        window.frame(app);  // loaded and rendered once
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
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

}  // namespace

int main(int argc, char** argv) {
    std::string scene = CAUSTICA_SOURCE_DIR "/scenes/default.lua";
    int changes = 30, frames = 300, width = 1280, height = 720;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--changes") && i + 1 < argc) changes = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--size") && i + 1 < argc && std::sscanf(argv[i + 1], "%dx%d", &width, &height) == 2) ++i;
        else if (!std::strcmp(argv[i], "--frames") && i + 1 < argc) frames = std::atoi(argv[++i]);
        else scene = argv[i];
    }
    const SceneScript script = load_scene_script(scene);
    const RenderJob& job = script.renders.at(0);
    std::printf("bench_preview: %s, %u hardware threads, %lld photons\n", scene.c_str(), std::thread::hardware_concurrency(),
                job.options.caustic_num_photons);
    latency(job, changes, width, height);
    latency_with_ui(scene, changes);
    std::printf("\nUI frame time, 1280 x 720 window, panels drawn (OSMesa llvmpipe), paced at 60 fps\n");
    std::printf("  %-46s %8s %8s %8s\n", "", "median", "p90", "max");
    frame_times(scene, frames, 1.0, true, "orbiting every frame, 512 x 512 render");
    frame_times(scene, frames, 1280.0 / 512.0, true, "orbiting every frame, 1280 x 1280 render");
    frame_times(scene, frames, 2.0, false, "still camera, 1024 x 1024 render running");
    frame_times(scene, frames, 1.0, false, "idle: render finished (the UI's own cost)", true);
    return 0;
}
