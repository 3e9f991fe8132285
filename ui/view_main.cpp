#include "ui/view_main.h"

#include "core/io/png_io.h"
#include "core/scene/source_location.h"
#include "ui/key_events.h"

#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <thread>

namespace caustica::ui {
namespace {

double now_seconds() {
    using clock = std::chrono::steady_clock;
    return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

constexpr double scripted_timeout_seconds = 600.0;

}  // namespace

ModelConfig model_config(const ViewArguments& args) {
    ModelConfig config;
    config.option_tokens = args.option_tokens;  // the scene given with them only
    config.option_scene = args.scene;
    config.recent_file = default_recent_file();
    Options options;
    apply_option_tokens(options, args.option_tokens);  // --script-timeout applies to every load
    config.script_timeout = options.script_timeout;
    config.script_memory_bytes = static_cast<std::size_t>(options.script_memory_mib) << 20;
    config.allow_read = args.allow_read;
    return config;
}

void start_view(ViewModel& model, PanelState& panels, const ViewArguments& args) {
    if (!args.scene.empty()) model.open(args.scene);
    if (args.overlay) {
        OverlaySettings overlay = model.overlay();
        overlay.enabled = true;
        model.set_overlay(overlay);
        panels.open_overlay_header = true;
    }
    if (args.orbit) model.orbit_when_loaded(*args.orbit);
}

ScriptedRun::ScriptedRun(const ViewArguments& args)
    : frames_wanted_(args.frames > 0 ? args.frames : 1), final_image_(args.final_image), waiting_for_key_(args.after_key),
      started_(now_seconds()) {}

bool ScriptedRun::done(const ViewModel& model) {
    if (waiting_for_key_ && !key_events().frame_presses().empty()) waiting_for_key_ = false;  // this frame saw it
    if (!waiting_for_key_) ++frames_;
    const PreviewDriver& driver = model.driver();
    bool ready = false;
    if (!model.loading()) {
        const bool idle_after_error = !model.error().empty() && !driver.busy() && !driver.pending();
        // A progressive preview without a stopping rule never finishes: --final waits for its first pass.
        const Options& o = driver.job().options;
        const bool endless = o.accumulates() && o.passes == 0 && o.time_limit <= 0.0 && o.target_error <= 0.0;
        const bool image_ready = !model.changes_pending() &&
                                 (final_image_ && !endless ? driver.finished() : driver.first_full_pass_done()) &&
                                 model.overlay_settled();
        ready = !model.has_scene() || image_ready || idle_after_error;
    }
    ready_frames_ = ready ? ready_frames_ + 1 : 0;
    if (!waiting_for_key_ && frames_ >= frames_wanted_ && ready_frames_ >= 3) return true;
    if (now_seconds() - started_ > scripted_timeout_seconds) {
        timed_out_ = true;
        return true;
    }
    return false;
}

void wait_for_frame(ViewModel& model, std::chrono::steady_clock::time_point next_frame) {
    for (;;) {
        model.poll();
        const auto now = std::chrono::steady_clock::now();
        if (now >= next_frame) return;
        std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(next_frame - now, std::chrono::microseconds(500)));
    }
}

void write_snapshot(const std::string& path, const std::vector<unsigned char>& rgba, int width, int height,
                    const std::string& platform) {
    Image image(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const unsigned char* p = &rgba[(static_cast<std::size_t>(y) * width + x) * 4];
            image.at(x, y) = glm::vec3(p[0], p[1], p[2]) / 255.0f;  // encodes back to the same bytes
        }
    write_png_atomic(path, image, PixelEncoding::clamped_linear,
                     {{"Software", "caustica " CAUSTICA_VERSION " (view snapshot)"}, {"caustica:platform", platform}});
}

int scripted_exit_code(const ViewModel& model, const ScriptedRun& run) {
    if (!model.error().empty()) std::fprintf(stderr, "caustica view: %s\n", model.error().c_str());
    if (run.timed_out()) {
        std::fprintf(stderr, "caustica view: gave up waiting for the render\n");
        return 1;
    }
    return scripted_exit_code(model.has_scene(), model.error(), false);
}

int view_main(int argc, char** argv, int (*run)(const ViewArguments&)) {
    try {
        const ViewArguments args = parse_view_arguments(std::vector<std::string>(argv + 1, argv + argc));
        if (args.help) {
            std::printf("%s", view_help().c_str());
            return 0;
        }
        if (!args.scene.empty() && !std::filesystem::is_regular_file(args.scene))
            throw InputError(not_a_scene_file(args.scene));  // before any window opens
        if (!args.snapshot.empty()) {
            if (const std::string problem = snapshot_target_problem(args.snapshot); !problem.empty()) {
                std::fprintf(stderr, "caustica view: %s\n", problem.c_str());
                return 1;  // an output problem, as for `caustica render`
            }
        }
        return run(args);
    } catch (const InputError& e) {
        std::fprintf(stderr, "caustica view: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "caustica view: %s\n", e.what());
        return 1;
    }
}

}  // namespace caustica::ui
