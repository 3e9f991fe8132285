#include "ui/tooltip.h"

#include <imgui.h>

namespace caustica::ui {

void wrapped_tooltip(const char* text) {
    ImGui::BeginTooltip();
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + tooltip_wrap_width(ImGui::GetIO().DisplaySize.x, ImGui::GetFontSize()));
    ImGui::TextUnformatted(text);
    ImGui::PopTextWrapPos();
    ImGui::EndTooltip();
}

bool item_wants_tooltip(bool when_disabled) {
    return ImGui::IsItemHovered(when_disabled ? ImGuiHoveredFlags_AllowWhenDisabled : ImGuiHoveredFlags_None) &&
           !ImGui::IsItemActive();
}

void hint(const char* text, bool when_disabled) {
    if (item_wants_tooltip(when_disabled)) wrapped_tooltip(text);
}

}  // namespace caustica::ui
