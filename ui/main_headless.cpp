// caustica-view-headless: the preview rendered off-screen with OSMesa, for tests and scripted
// screenshots. `caustica view` execs this without a DISPLAY or with --headless.
#include "ui/headless_window.h"
#include "ui/view_main.h"

#include <chrono>
#include <cstdio>
#include <thread>

namespace {

using namespace caustica::ui;

int run_headless(const ViewArguments& args) {
    HeadlessWindow window(args.width, args.height);
    ViewModel model(model_config(args));
    ViewApp app(model);
    start_view(model, app.panels(), args);
    ViewArguments scripted = args;
    if (!scripted.scripted()) {
        std::fprintf(stderr, "caustica view: headless, the preview renders until the first full pass; "
                             "--snapshot FILE.png keeps the window\n");
    }
    ScriptedRun run(scripted);
    const auto frame_time = std::chrono::microseconds(16667);
    auto next_frame = std::chrono::steady_clock::now();
    for (;;) {
        window.frame(app);
        if (run.done(model)) break;
        next_frame += frame_time;  // 60 frames a second at most: the renderer needs the cores
        const auto now = std::chrono::steady_clock::now();
        if (next_frame > now) wait_for_frame(model, next_frame);
        else next_frame = now;
    }
    if (!args.snapshot.empty()) {
        write_snapshot(args.snapshot, window.pixels(), window.width(), window.height(), "osmesa");
        std::printf("wrote %s (%d x %d)\n", args.snapshot.c_str(), window.width(), window.height());
    }
    if (!model.error().empty()) std::fprintf(stderr, "caustica view: %s\n", model.error().c_str());
    if (run.timed_out()) {
        std::fprintf(stderr, "caustica view: gave up waiting for the render\n");
        return 1;
    }
    return model.has_scene() ? 0 : 2;
}

}  // namespace

int main(int argc, char** argv) { return view_main(argc, argv, run_headless); }
