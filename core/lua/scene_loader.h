// Runs a scene script (the gr.* language of SCENE_API.md) in a sandbox and returns its renders.
#pragma once

#include "core/scene/scene_desc.h"

#include <atomic>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace caustica {

/// Limits and inputs for running a scene script.
struct LoadSettings {
    Options base_options;                      ///< defaults the script's gr.option calls start from
    double timeout_seconds = 60.0;             ///< wall-clock limit of script evaluation, 0 = none
    std::size_t memory_limit_bytes = std::size_t(2) << 30;  ///< Lua heap cap
    const std::atomic<bool>* cancel = nullptr; ///< set by Ctrl-C: stops the script promptly
    std::vector<std::string> allow_read;       ///< folders besides the scene's that it may read (--allow-read)
    bool output_given = false;                 ///< -o given: gr.render's file names are not used (nor checked)
};

/// Thrown by load_scene_script when LoadSettings::cancel is set while the script runs.
class ScriptCancelled : public std::runtime_error {
public:
    ScriptCancelled() : std::runtime_error("interrupted") {}
};

/// Runs the script at `path` and returns every gr.render it made, in order. The script runs in a
/// separate process (scene_process.cpp): past the time limit plus a grace period, on cancel, or
/// should the interpreter crash, that process is stopped from outside and nothing of it remains
/// in this one. Throws InputError with "file:line: call: message" on any problem in the script,
/// ScriptCancelled when `settings.cancel` is set.
SceneScript load_scene_script(const std::string& path, const LoadSettings& settings = {});

/// The same in the calling process (fuzzing, tests of the interpreter itself): the time limit is
/// checked by the instruction hook and inside the bounded library loops only.
SceneScript load_scene_script_in_process(const std::string& path, const LoadSettings& settings = {});

}  // namespace caustica
