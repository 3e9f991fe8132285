// The command line of `caustica view` (shared by the windowed and the headless executables).
#pragma once

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace caustica::ui {

/// Parsed `caustica view` arguments.
struct ViewArguments {
    std::vector<std::string> allow_read;  ///< --allow-read folders: scenes may read there too
    std::string scene;                   ///< "" = start with the Open panel
    int frames = 0;                      ///< --frames N: run N frames (at least until the first full pass), then exit
    std::string snapshot;                ///< --snapshot FILE: write the whole window to FILE before exiting
    bool overlay = false;                ///< --overlay: projection-map overlay on from the start
    std::optional<glm::dvec2> orbit;     ///< --orbit YAW,PITCH: orbit by these degrees before rendering
    bool headless = false;               ///< --headless: OSMesa, no window
    bool final_image = false;            ///< --final: wait for every pass (not only the first) before the snapshot
    bool after_key = false;              ///< --after-key: count --frames from the first key pressed (tests that send keys)
    int width = 1280, height = 720;      ///< --size WxH: the window
    std::vector<std::string> option_tokens;  ///< render options, as for `caustica render`
    bool help = false;

    /// Whether the run ends by itself (frames or snapshot given) instead of waiting for the person.
    bool scripted() const { return frames > 0 || !snapshot.empty(); }
};

/// Parses the arguments after `view`. Throws InputError naming the bad argument.
ViewArguments parse_view_arguments(const std::vector<std::string>& args);

/// Why a --snapshot target cannot be written ("" = fine): a folder, or a folder that is missing or
/// not writable. Checked before any window opens (exit 1, an output problem, as for `caustica
/// render`), so that it is not found out only after rendering.
std::string snapshot_target_problem(const std::string& path);

/// The exit code of a scripted run (--frames/--snapshot) that ended: 1 it gave up waiting, 2 no
/// scene or an error shown at the end (the scene's or its render's, as `caustica render` exits 2
/// for it), else 0.
int scripted_exit_code(bool has_scene, const std::string& error, bool timed_out);

/// The text of `caustica view --help`.
std::string view_help();

}  // namespace caustica::ui
