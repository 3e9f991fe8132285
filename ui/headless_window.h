// The preview without a window: an OSMesa OpenGL 3.3 core context rendering into memory, and
// ImGui driven without a platform backend (mouse, keys, size and time filled in by hand).
// Used by caustica-view-headless, the UI tests and the preview benchmark; links libOSMesa, so it
// never goes into an executable that links libOpenGL.
#pragma once

#include "ui/frame_pacing.h"
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
    std::vector<int> taps = {};       ///< keys pressed and released again before this frame (a tap
                                      ///< shorter than a frame): reported to ui/key_events.h as the
                                      ///< window's key callback does, which shows them down for one frame
    bool ctrl = false, shift = false, alt = false;
};

/// An off-screen window: OSMesa context, ImGui context and its OpenGL3 renderer.
class HeadlessWindow {
public:
    /// Creates the context; throws std::runtime_error when OSMesa or the GL loader fails.
    HeadlessWindow(int width, int height);
    ~HeadlessWindow();
    HeadlessWindow(const HeadlessWindow&) = delete;
    HeadlessWindow& operator=(const HeadlessWindow&) = delete;

    /// Runs one frame of `app` with `input` and finishes drawing it (unless skip_undrawable_frames).
    void frame(ViewApp& app, const HeadlessInput& input = {});
    /// Lets frames skip drawing as the window does (ui/frame_pacing.h, FrameSkipper) for the
    /// app showing `model`, when `on`; by default every frame is drawn, so that pixels() always
    /// shows the last frame (the tests). The model's frames are followed from here on either way.
    void skip_undrawable_frames(const ViewModel* model, bool on = true);
    /// Whether the last frame was drawn.
    bool last_frame_drawn() const { return drawn_; }
    /// The window's pixels, RGBA8, top row first.
    std::vector<unsigned char> pixels() const;

    /// Where the last frame's time went, in milliseconds (the preview benchmark's breakdown).
    struct FrameTimes {
        double build = 0.0;  ///< ViewApp::frame: input, model update, texture upload, panels
        double draw = 0.0;   ///< the image, the overlay and ImGui's draw data, until glFinish
        double draw_image = 0.0;  ///< of which the image and the overlay (ViewApp::draw, glFinish)
    };
    const FrameTimes& last_frame_times() const { return times_; }
    /// Whether draw_image is measured (a glFinish between the image and the panels).
    void measure_draw(bool on) { measure_draw_ = on; }

    /// The window's size in pixels.
    int width() const { return width_; }
    int height() const { return height_; }

private:
    struct Context;
    std::unique_ptr<Context> context_;
    int width_, height_;
    std::vector<int> released_;  // keys to lift at the next frame
    std::chrono::steady_clock::time_point last_frame_;
    FrameTimes times_;
    bool measure_draw_ = false, drawn_ = false;
    const ViewModel* skip_for_ = nullptr;
    bool skipping_ = false;
    FrameSkipper skipper_;
};

}  // namespace caustica::ui
