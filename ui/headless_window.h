// The preview without a window: an OSMesa OpenGL 3.3 core context rendering into memory, and
// ImGui driven without a platform backend (mouse, keys, size and time filled in by hand).
// Used by caustica-view-headless, the UI tests and the preview benchmark; links libOSMesa, so it
// never goes into an executable that links libOpenGL.
#pragma once

#include "ui/view_app.h"

#include <glm/glm.hpp>

#include <chrono>
#include <memory>
#include <vector>

namespace caustica::ui {

/// Input for one headless frame (window pixels, y down).
struct HeadlessInput {
    glm::vec2 mouse{-1e30f, -1e30f};  ///< far away = no mouse
    bool buttons[3] = {false, false, false};  ///< left, right, middle held
    float wheel = 0.0f;
    std::vector<int> keys;            ///< keys pressed this frame (ui/keys.h numbers); a key listed
                                      ///< in two frames in a row is held, not pressed twice
    bool ctrl = false, shift = false;
};

/// An off-screen window: OSMesa context, ImGui context and its OpenGL3 renderer.
class HeadlessWindow {
public:
    /// Creates the context; throws std::runtime_error when OSMesa or the GL loader fails.
    HeadlessWindow(int width, int height);
    ~HeadlessWindow();
    HeadlessWindow(const HeadlessWindow&) = delete;
    HeadlessWindow& operator=(const HeadlessWindow&) = delete;

    /// Runs one frame of `app` with `input` and finishes drawing it.
    void frame(ViewApp& app, const HeadlessInput& input = {});
    /// The window's pixels, RGBA8, top row first.
    std::vector<unsigned char> pixels() const;

    /// The window's size in pixels.
    int width() const { return width_; }
    int height() const { return height_; }

private:
    struct Context;
    std::unique_ptr<Context> context_;
    int width_, height_;
    std::vector<int> released_;  // keys to lift at the next frame
    std::chrono::steady_clock::time_point last_frame_;
};

}  // namespace caustica::ui
