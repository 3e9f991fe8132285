// Helpers of the UI tests: temporary folders, scene files, and running the model until a condition.
#pragma once

#include "ui/view_model.h"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <unistd.h>

namespace caustica::ui::testing {

namespace fs = std::filesystem;

/// A fresh folder under the system temp dir, removed at the end of the test.
class TempFolder {
public:
    TempFolder() {
        static int counter = 0;
        path_ = fs::temp_directory_path() / ("caustica_ui_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempFolder() {
        std::error_code ignored;
        fs::remove_all(path_, ignored);
    }
    /// Writes `text` to `name` and returns the full path.
    std::string write(const std::string& name, const std::string& text) const {
        const fs::path file = path_ / name;
        std::ofstream(file, std::ios::binary) << text;
        return file.string();
    }
    /// The full path of `name` in the folder.
    std::string file(const std::string& name) const { return (path_ / name).string(); }

private:
    fs::path path_;
};

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
