#include "ui/shortcuts.h"

#include "ui/keys.h"

#include <algorithm>

namespace caustica::ui {
namespace {

constexpr int ctrl = key_mods::ctrl, alt = key_mods::alt, shift = key_mods::shift;
constexpr int key_i = 73, key_l = 76;  // GLFW numbers: ASCII for letters

}  // namespace

const std::vector<ShortcutBinding>& shortcut_bindings() {
    using S = Shortcut;
    static const std::vector<ShortcutBinding> bindings = {
        {S::help, keys::f1, 0, false, true},
        {S::close_help, keys::escape, 0},
        {S::script_camera, keys::home, 0, false, true},
        {S::script_camera, keys::r, ctrl},
        {S::reload, keys::f5, 0, false, true},
        {S::pause, keys::space, 0, false, true},
        {S::outline, keys::o, alt},
        {S::cells, keys::c, alt},
        {S::photons_only, keys::p, alt},
        {S::photon_dots, keys::d, alt},
        {S::next_layer, key_l, alt},
        {S::exposure_up, keys::e, alt},
        {S::exposure_down, keys::e, alt | shift},
        {S::exposure_reset, keys::e, ctrl},
        {S::srgb, keys::g, alt},
        {S::orbit_left, keys::left, 0, true, true},
        {S::orbit_right, keys::right, 0, true, true},
        {S::orbit_up, keys::up, 0, true, true},
        {S::orbit_down, keys::down, 0, true, true},
        {S::zoom_in, keys::equal, ctrl, true},
        {S::zoom_in, keys::keypad_add, ctrl, true},
        {S::zoom_out, keys::minus, ctrl, true},
        {S::zoom_out, keys::keypad_subtract, ctrl, true},
        {S::toggle_panels, keys::tab, 0},
        {S::fit_image, keys::f, alt},
        {S::image_one_to_one, keys::one, alt},
        {S::snapshot, keys::b, alt},
        {S::compare, keys::a, alt},
        {S::readout, key_i, alt},
        {S::save, keys::s, ctrl},
        {S::quit, keys::q, ctrl},
        {S::undo, keys::z, ctrl, true},
        {S::redo, keys::z, ctrl | shift, true},
        {S::redo, keys::y, ctrl, true},
    };
    return bindings;
}

bool types_text(int key, int mods) {
    const bool printable = key >= keys::space && key < keys::escape;  // GLFW: the printable keys lie below Esc
    const bool keypad_sign = key >= 320 && key <= 336 && key != keys::keypad_enter;  // keypad digits and signs
    return (printable || keypad_sign) && (mods & (key_mods::ctrl | key_mods::alt | key_mods::super)) == 0;
}

std::vector<Shortcut> shortcuts_pressed(const KeyEvents& events, bool keyboard_taken) {
    std::vector<Shortcut> actions;
    if (keyboard_taken) return actions;
    for (const ShortcutBinding& b : shortcut_bindings()) {
        const bool pressed = events.pressed_with(b.key, b.mods, b.repeats) ||
                             (b.shift_too && events.pressed_with(b.key, b.mods | key_mods::shift, b.repeats));
        if (pressed && std::find(actions.begin(), actions.end(), b.action) == actions.end()) actions.push_back(b.action);
    }
    return actions;
}

std::vector<std::pair<std::string, std::string>> shortcut_help_rows() {
    // Plain letters type; they never act (docs/PREVIEW.md, "Keys and mouse").
    return {
        {"left drag", "orbit around the target"},
        {"right or middle drag", "pan"},
        {"wheel, Ctrl+= / Ctrl+-", "zoom"},
        {"double-click", "set the target on the surface under the cursor"},
        {"arrow keys", "move the camera 5 degrees right, left, up, down (as --orbit 5,0 ... 0,-5)"},
        {"Home, Ctrl+R", "back to the script's camera"},
        {"Alt+O / Alt+C", "projection-map outline / occupied cells"},
        {"Alt+P / Alt+D", "photons-only view / photon dots"},
        {"Alt+L", "show the next layer: image, direct, indirect, caustic, background, albedo, normal"},
        {"Space", "pause / resume the refinement"},
        {"Alt+E / Alt+Shift+E / Ctrl+E", "exposure up / down one stop / back to 0"},
        {"Alt+G", "sRGB display"},
        {"F5", "reload the scene (it also reloads by itself)"},
        {"Shift+left drag, Ctrl+B then drag", "render region: every pass goes to the box, the rest keeps its image"},
        {"Ctrl+Alt+B", "clear the render region (the whole image again)"},
        {"Ctrl+S", "save the image (while rendering: now or when done)"},
        {"Ctrl+Z / Ctrl+Shift+Z, Ctrl+Y",
         "undo / redo a change of the knobs, preset or stopping rules (a restarted accumulation comes back "
         "with its passes)"},
        {"Tab / the >> button", "hide or show the sidebar (the image takes the whole window)"},
        {"Ctrl+wheel", "zoom the image about the cursor (whole factors above 1:1, sharp pixels)"},
        {"Ctrl+left drag", "move the zoomed image"},
        {"Alt+F / Alt+1", "fit the image / pixels 1:1"},
        {"Alt+B", "snapshot the image as the A/B reference"},
        {"Alt+A", "compare: off, split, difference, relative error (drag the split line)"},
        {"Alt+I", "hover readout on / off (pixel, surface, caustic; shows when the mouse rests on the image)"},
        {"drag a knob / Shift+drag", "change it by 1 % / 10 % a pixel (Ctrl+click: type a value)"},
        {"drop a .lua file", "open it"},
        {"F1", "this help"},
        {"Esc", "close this help"},
        {"Ctrl+Q", "quit"},
        {"letters, digits, signs", "nothing without Ctrl or Alt: typing never acts"},
    };
}

}  // namespace caustica::ui
