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
    int width = 1280, height = 720;      ///< --size WxH: the window
    std::vector<std::string> option_tokens;  ///< render options, as for `caustica render`
    bool help = false;

    /// Whether the run ends by itself (frames or snapshot given) instead of waiting for the person.
    bool scripted() const { return frames > 0 || !snapshot.empty(); }
};

/// Parses the arguments after `view`. Throws InputError naming the bad argument.
ViewArguments parse_view_arguments(const std::vector<std::string>& args);

/// The text of `caustica view --help`.
std::string view_help();

}  // namespace caustica::ui
