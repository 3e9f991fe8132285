// Helpers of the UI tests: temporary folders, scene files, and running the model until a condition.
#pragma once

#include "tests/temp_folder.h"
#include "ui/view_model.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>
#include <unistd.h>

namespace caustica::ui::testing {

namespace fs = std::filesystem;

using caustica::testing::TempFolder;

/// The preview test scene (tests/ui/scenes/caustic_box.lua) with `extra` Lua appended before its
/// render call and `photons` caustic photons.
inline std::string caustic_box_text(long long photons = 2000000, const std::string& extra = "") {
    std::ifstream in(std::string(CAUSTICA_SOURCE_DIR) + "/tests/ui/scenes/caustic_box.lua");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string option = "gr.option('--caustic-num-photons 2000000')";
    const auto at = text.find(option);
    if (at != std::string::npos)
        text.replace(at, option.size(), "gr.option('--caustic-num-photons " + std::to_string(photons) + "')\n" + extra);
    return text;
}

/// The names of the files in `folder`, sorted.
inline std::vector<std::string> files_in(const fs::path& folder) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(folder)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

/// The bytes of the file at `path` ("" if it cannot be read).
inline std::string file_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Calls model.update() (about every millisecond) until `done` or `seconds` pass; returns `done()`.
inline bool run_until(ViewModel& model, const std::function<bool()>& done, double seconds = 60.0) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        model.update();
        if (done()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return done();
}

/// Runs until the model shows a finished render of everything asked so far.
inline bool run_until_finished(ViewModel& model, double seconds = 60.0) {
    return run_until(model, [&] { return !model.changes_pending() && model.driver().finished(); }, seconds);
}

}  // namespace caustica::ui::testing
