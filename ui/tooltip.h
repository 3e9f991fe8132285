// Tooltips that stay inside the window: every panel's hints go through here, wrapped at a width
// that fits the window (a long hint on one line would run past its edge).
#pragma once

#include <algorithm>

namespace caustica::ui {

/// The widest a tooltip's text is wrapped at, in multiples of the font size.
inline constexpr float tooltip_em = 32.0f;
/// Pixels a tooltip keeps from the window's edges (its padding included).
inline constexpr float tooltip_margin = 24.0f;

/// The text width tooltips wrap at in a window `display_width` pixels wide with a font
/// `font_size` pixels high: tooltip_em font sizes, narrowed to what the window holds between its
/// margins (at least 8 font sizes, for windows too narrow for anything better).
inline float tooltip_wrap_width(float display_width, float font_size) {
    return std::max(8.0f * font_size, std::min(tooltip_em * font_size, display_width - 2.0f * tooltip_margin));
}

/// Shows `text` as a tooltip now, wrapped to fit the window.
void wrapped_tooltip(const char* text);

/// Whether the last item's tooltip should show: hovered (also disabled, when `when_disabled`) and
/// not held, so that a knob being dragged does not cover the rows below it.
bool item_wants_tooltip(bool when_disabled = false);

/// The last item's tooltip: `text`, wrapped to fit the window, while item_wants_tooltip().
void hint(const char* text, bool when_disabled = false);

}  // namespace caustica::ui
