// What the windowed and the headless executables share around their frame loops: the command
// line, setting up the model from it, when a scripted run (--frames, --snapshot) may end, and
// writing the window's pixels as a PNG.
#pragma once

#include "ui/panels.h"
#include "ui/view_arguments.h"
#include "ui/view_model.h"

#include <chrono>
#include <string>
#include <vector>

namespace caustica::ui {

/// The model's configuration for a command line.
ModelConfig model_config(const ViewArguments& args);

/// Applies the start-up arguments: opens the scene, turns the overlay on, queues --orbit.
void start_view(ViewModel& model, PanelState& panels, const ViewArguments& args);

/// Decides when a scripted run has seen enough frames.
class ScriptedRun {
public:
    explicit ScriptedRun(const ViewArguments& args);
    /// Call after each frame; true once --frames frames ran and the image is ready: the first
    /// full-resolution pass (every pass with --final) and the overlay are done, for three frames
    /// in a row (so that the last tiles and the panels' sizes have settled), or a scene error is shown.
    /// With --after-key, frames count only from the frame that saw the first key press.
    bool done(const ViewModel& model);
    /// Whether the run gave up waiting (timed out).
    bool timed_out() const { return timed_out_; }

private:
    int frames_wanted_, frames_ = 0, ready_frames_ = 0;
    bool final_image_, waiting_for_key_;
    double started_;
    bool timed_out_ = false;
};

/// Waits until `next_frame`, meanwhile letting the model restart the renderer the moment it
/// has stopped (instead of at the next frame).
void wait_for_frame(ViewModel& model, std::chrono::steady_clock::time_point next_frame);

/// Writes RGBA8 pixels (top row first) as an RGB PNG, atomically; `platform` ("glfw", "osmesa")
/// goes into its caustica:platform text chunk.
void write_snapshot(const std::string& path, const std::vector<unsigned char>& rgba, int width, int height,
                    const std::string& platform);

/// The common main: parses argv (after the program name) and hands the arguments to `run`.
/// Prints help and argument errors itself. Returns the exit code.
int view_main(int argc, char** argv, int (*run)(const ViewArguments&));

/// The exit code of a scripted run (--frames/--snapshot) that ended, after printing what went
/// wrong: 1 it gave up waiting, 2 no scene or the scene (or its render) ends with an error shown,
/// as `caustica render` exits 2 for it; else 0.
int scripted_exit_code(const ViewModel& model, const ScriptedRun& run);

}  // namespace caustica::ui
