// Key presses as the platform saw them, kept until the next frame. Dear ImGui 1.86 finds a press
// by comparing io.KeysDown between two frames, so a key pressed and released within one frame (a
// quick tap, ~15 ms, at 60 frames a second or slower) never reaches IsKeyPressed. The platform
// therefore also records every press here, from GLFW's key callback (ui/main_window.cpp) or from
// the headless platform's synthetic input (ui/headless_window.cpp), and ViewApp asks this queue.
// GL-free and ImGui-free: the key numbers are those of ui/keys.h (GLFW's, = io.KeysDown indices).
#pragma once

#include <cstddef>
#include <vector>

namespace caustica::ui {

/// Modifier bits held with a press: GLFW's GLFW_MOD_* values, so the window passes `mods` through.
namespace key_mods {
inline constexpr int shift = 0x1, ctrl = 0x2, alt = 0x4, super = 0x8;
inline constexpr int all = shift | ctrl | alt | super;  ///< the bits compared (Caps/Num Lock are not)
}  // namespace key_mods

/// One press of a key, or one auto-repeat of a held key.
struct KeyPress {
    int key = 0;          ///< ui/keys.h number
    int mods = 0;         ///< key_mods bits held when it was pressed
    bool repeat = false;  ///< an auto-repeat of a key held down, not a new press
};

/// The presses between two frames, handed to the frame that follows them.
class KeyEvents {
public:
    /// At most this many presses wait for a frame; later ones are dropped (a stalled frame loop
    /// must not grow memory, and nobody types 256 keys within a frame).
    static constexpr std::size_t max_pending = 256;

    /// Platform side, any time between frames: records a press (or an auto-repeat if `repeat`).
    /// A press counts whether or not its key is still down when the frame begins.
    void press(int key, int mods = 0, bool repeat = false);
    /// Platform side: records a release. Only needed for taps(): a key released before the frame
    /// that follows its press.
    void release(int key);
    /// Starts a frame: the presses recorded since the previous call become this frame's; the
    /// previous frame's are forgotten (each press is seen in exactly one frame).
    void begin_frame();

    /// Keys pressed and released again before this frame began. ImGui's own widgets (Enter in a
    /// text field, Esc in a popup) read io.KeysDown, which never showed them down: the platform
    /// sets them down for this one frame, and lifts them at the next (lifts()).
    const std::vector<int>& taps() const { return taps_; }
    /// The previous frame's taps, to lift in io.KeysDown now (unless the key is held down again).
    const std::vector<int>& lifts() const { return lifts_; }
    /// Forgets everything, recorded and current (a new window, a new test).
    void clear();

    /// Whether `key` was pressed during this frame, whatever modifiers were held; auto-repeats
    /// count too if `repeat` (as ImGui::IsKeyPressed(key, repeat)).
    bool pressed(int key, bool repeat = false) const { return count(key, repeat) > 0; }
    /// Whether `key` was pressed during this frame with exactly the modifiers `mods` (key_mods bits).
    bool pressed_with(int key, int mods, bool repeat = false) const;
    /// How many times `key` was pressed during this frame (two quick taps of an arrow within one
    /// frame are two steps).
    int count(int key, bool repeat = false) const;
    /// This frame's presses, in the order they happened.
    const std::vector<KeyPress>& frame_presses() const { return frame_; }

private:
    std::vector<KeyPress> pending_, frame_;
    std::vector<int> pressed_, pending_taps_, taps_, lifts_;  // pressed_: keys pressed since begin_frame()
};

/// The process's queue: the platform fills it and starts its frames, ViewApp reads it.
KeyEvents& key_events();

/// Whether `imgui_key` (a ui/keys.h number, an io.KeysDown index) was pressed this frame, even if
/// it was released again before the frame began; `repeat` as in ImGui::IsKeyPressed. Replaces
/// ImGui::IsKeyPressed in ViewApp. Does not look at io.WantCaptureKeyboard: the caller decides
/// which shortcuts still work while a text field has the keyboard.
bool key_pressed(int imgui_key, bool repeat = false);
/// The same with exactly the modifiers `mods` held at the press (key_mods bits), for shortcuts
/// such as Ctrl+Shift+Z that a quick tap may release before the frame reads io.KeyCtrl.
bool key_pressed_with(int imgui_key, int mods, bool repeat = false);

}  // namespace caustica::ui
