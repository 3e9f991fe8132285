// The headless snapshot tests' fixture: an OSMesa window, a model and the app with a scene
// loaded, run frame by frame; pixel access and the README's screenshot hook.
#pragma once

#include "ui/headless_window.h"
#include "ui_test_support.h"

#include "core/io/png_io.h"

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace caustica::ui::testing {

inline constexpr int window_width = 1280, window_height = 720;

struct Rgb {
    int r, g, b;
    bool operator==(const Rgb&) const = default;
};

/// A pixel of a window snapshot (RGBA, top row first).
inline Rgb pixel(const std::vector<unsigned char>& rgba, int x, int y) {
    const unsigned char* p = &rgba[(static_cast<std::size_t>(y) * window_width + x) * 4];
    return {p[0], p[1], p[2]};
}

/// $CAUSTICA_DOC_IMAGES made absolute when the test program starts (a test may change the
/// current folder), or empty.
inline const std::string doc_images_folder = [] {
    const char* folder = std::getenv("CAUSTICA_DOC_IMAGES");
    return folder && *folder ? std::filesystem::absolute(folder).string() : std::string();
}();

/// Writes a snapshot to $CAUSTICA_DOC_IMAGES/name when that is set (the docs' screenshots).
inline void write_doc_image(const std::vector<unsigned char>& rgba, const std::string& name) {
    if (doc_images_folder.empty()) return;
    const std::string& folder = doc_images_folder;
    Image image(window_width, window_height);
    for (int y = 0; y < window_height; ++y)
        for (int x = 0; x < window_width; ++x) {
            const Rgb p = pixel(rgba, x, y);
            image.at(x, y) = (glm::vec3(p.r, p.g, p.b) + 0.5f) / 255.0f;  // truncated back to p
        }
    write_png_atomic(folder + "/" + name, image, PixelEncoding::clamped_linear);
}

/// The window, the model and the app, with `scene_text` loaded (reproducible, two threads).
class HeadlessPreview {
public:
    explicit HeadlessPreview(const std::string& scene_text) {
        ModelConfig config;
        config.option_tokens = {"--reproducible", "--threads", "2"};
        model = std::make_unique<ViewModel>(config);
        app = std::make_unique<ViewApp>(*model);
        scene = folder.write("scene.lua", scene_text);
        model->open(scene);
    }

    /// Runs frames (about 1 ms apart) until `done` and then three more; false on timeout.
    bool run_until(const std::function<bool()>& done, double seconds = 60.0) {
        const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        while (!done()) {
            if (std::chrono::steady_clock::now() > end) return false;
            window.frame(*app);
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        for (int i = 0; i < 3; ++i) window.frame(*app);
        return true;
    }
    /// Runs until everything asked for is rendered and the overlay (when on) is traced.
    bool settle() {
        return run_until([&] { return !model->changes_pending() && model->driver().finished() && model->overlay_settled(); });
    }
    /// One frame with input.
    void frame(const HeadlessInput& input) { window.frame(*app, input); }
    /// The window's pixels.
    std::vector<unsigned char> snapshot() const { return window.pixels(); }

    TempFolder folder;
    std::string scene;
    HeadlessWindow window{window_width, window_height};  // before the model and app: destroyed last
    std::unique_ptr<ViewModel> model;
    std::unique_ptr<ViewApp> app;
};

}  // namespace caustica::ui::testing
