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

void hint(const char* text, bool when_disabled) {
    if (ImGui::IsItemHovered(when_disabled ? ImGuiHoveredFlags_AllowWhenDisabled : ImGuiHoveredFlags_None))
        wrapped_tooltip(text);
}

}  // namespace caustica::ui
