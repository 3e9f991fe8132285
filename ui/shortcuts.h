// The preview's keyboard shortcuts (docs/PREVIEW.md, "Keys and mouse"): which actions the presses
// of a frame ask for. Typing never acts: every shortcut is a key that types nothing (F1, F5, Esc,
// Home, Tab, the arrows, Space) or a letter, digit or sign held with Ctrl or Alt, so that letters
// typed after a missed click change nothing; and no shortcut acts while a text field or another
// widget has the keyboard. GL-free and ImGui-free: the key queue (ui/key_events.h) is all it reads.
#pragma once

#include "ui/key_events.h"

#include <string>
#include <utility>
#include <vector>

namespace caustica::ui {

/// What a shortcut does.
enum class Shortcut {
    help, close_help, script_camera, reload, pause, outline, cells, photons_only, photon_dots, exposure_up,
    exposure_down, exposure_reset, srgb, orbit_left, orbit_right, orbit_up, orbit_down, zoom_in, zoom_out,
    toggle_panels, fit_image, image_one_to_one, snapshot, compare, readout, save, quit, undo, redo, next_layer,
};

/// One key (with exact modifiers) bound to an action.
struct ShortcutBinding {
    Shortcut action;
    int key;                  ///< ui/keys.h number
    int mods;                 ///< key_mods bits that must be held, exactly
    bool repeats = false;     ///< auto-repeats of a held key act again (arrows, zoom, undo)
    bool shift_too = false;   ///< the key also acts with Shift added (keys that type nothing)
};

/// Every binding, in the order the help lists them.
const std::vector<ShortcutBinding>& shortcut_bindings();

/// Whether `key` held with `mods` could be typed into a text field: a printable key (letters,
/// digits, signs, Space) with neither Ctrl nor Alt nor Super. Such a press is never a shortcut but
/// Space's pause, which loses nothing (docs/PREVIEW.md, "Keys and mouse").
bool types_text(int key, int mods);

/// The actions this frame's presses ask for, each once, in binding order. `keyboard_taken`: a
/// text field is being edited or another widget is active (ImGui's io.WantTextInput or
/// io.WantCaptureKeyboard): then none.
std::vector<Shortcut> shortcuts_pressed(const KeyEvents& events, bool keyboard_taken);

/// The help's rows (F1): what to press, and what it does; the keys from the bindings.
std::vector<std::pair<std::string, std::string>> shortcut_help_rows();

}  // namespace caustica::ui
