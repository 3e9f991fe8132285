// caustica-view-headless: the preview rendered off-screen with OSMesa, for tests and scripted
// screenshots. `caustica view` execs this without a DISPLAY or with --headless.
#include "ui/frame_pacing.h"
#include "ui/headless_window.h"
#include "ui/view_main.h"

#include <chrono>
#include <cstdio>
#include <thread>

namespace {

using namespace caustica::ui;

int run_headless(const ViewArguments& args) {
    if (args.after_key) {  // nobody can press one: the run would only time out
        std::fprintf(stderr, "caustica view: --after-key needs the window (keys); the headless preview has none\n");
        return 2;
    }
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
    window.skip_undrawable_frames(&model);  // a finished run's frames are drawn: the snapshot is the last
    for (;;) {
        const auto frame_start = std::chrono::steady_clock::now();
        window.frame(app);
        if (run.done(model)) break;
        wait_for_next_frame(model, frame_start);  // 60 frames a second at most: the renderer needs the cores
    }
    if (!args.snapshot.empty()) {
        if (!window.last_frame_drawn()) {  // a run that gave up may end on a skipped frame: draw the last state
            window.skip_undrawable_frames(&model, false);
            window.frame(app);
        }
        write_snapshot(args.snapshot, window.pixels(), window.width(), window.height(), "osmesa");
        std::printf("wrote %s (%d x %d)\n", args.snapshot.c_str(), window.width(), window.height());
    }
    return scripted_exit_code(model, run);
}

}  // namespace

int main(int argc, char** argv) { return view_main(argc, argv, run_headless); }
