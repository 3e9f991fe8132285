// Key numbers of io.KeysDown[]: GLFW's (the GLFW backend fills them so; the headless platform
// uses the same numbers), named here so that shared code does not include GLFW.
#pragma once

namespace caustica::ui::keys {

/// Printable keys: their upper-case ASCII codes.
inline constexpr int space = 32, minus = 45, one = 49, equal = 61;
/// Letters used by the preview and by ImGui's text fields.
inline constexpr int a = 65, b = 66, c = 67, d = 68, e = 69, f = 70, g = 71, h = 72, o = 79, p = 80, q = 81, r = 82,
                     s = 83, v = 86, x = 88, y = 89, z = 90;
/// Editing and navigation keys.
inline constexpr int escape = 256, enter = 257, tab = 258, backspace = 259, insert = 260, del = 261;
/// Arrow keys.
inline constexpr int right = 262, left = 263, down = 264, up = 265;
/// Page and line navigation.
inline constexpr int page_up = 266, page_down = 267, home = 268, end = 269;
/// Function keys used by the preview.
inline constexpr int f1 = 290, f5 = 294;
/// Keypad keys used by the preview.
inline constexpr int keypad_subtract = 333, keypad_add = 334, keypad_enter = 335;

}  // namespace caustica::ui::keys
