// The sidebar that holds every section, and saving with its overwrite question.
#include "ui/panels.h"

#include <imgui.h>

#include <cstring>

namespace caustica::ui {

void apply_panel_style() {
    ImGui::StyleColorsDark();
    ImGuiStyle& style = ImGui::GetStyle();
    style.FramePadding = ImVec2(4.0f, 2.0f);
    style.ItemSpacing = ImVec2(8.0f, 3.0f);
    style.WindowRounding = 0.0f;
}

void draw_sidebar(ViewModel& model, PanelState& state, glm::vec2 window) {
    ImGui::SetNextWindowPos(ImVec2(window.x - sidebar_width, 0.0f));
    ImGui::SetNextWindowSize(ImVec2(sidebar_width, window.y));
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                   ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings;
    ImGui::Begin("caustica preview", nullptr, flags);
    ImGui::PushItemWidth(-150.0f);  // room for the labels on the right
    if (ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) draw_scene_section(model, state);
    if (ImGui::CollapsingHeader("Light transport and caustics", ImGuiTreeNodeFlags_DefaultOpen)) draw_caustics_section(model, state);
    if (ImGui::CollapsingHeader("View and save")) draw_view_section(model, state);
    if (ImGui::CollapsingHeader("Statistics", ImGuiTreeNodeFlags_DefaultOpen)) draw_stats_section(model, state);
    ImGui::PopItemWidth();
    ImGui::End();
}

void show_message(PanelState& state, const std::string& text) {
    state.message = text;
    state.message_until = ImGui::GetTime() + 4.0;
}

void request_save(ViewModel& model, PanelState& state) {
    if (state.save_path[0] == '\0') {
        const std::string proposed = model.default_save_path();
        std::strncpy(state.save_path.data(), proposed.c_str(), state.save_path.size() - 1);
    }
    const SaveResult result = model.save(state.save_path.data(), false);
    if (result.outcome == SaveOutcome::exists) state.ask_overwrite = true;
    else show_message(state, result.message);
}

}  // namespace caustica::ui
