// The sidebar that holds every section, and saving with its overwrite question.
#include "ui/panels.h"

#include <imgui.h>

#include <algorithm>
#include <cstring>
#include <filesystem>

namespace caustica::ui {

void apply_panel_style() {
    ImGui::StyleColorsDark();
    ImGuiStyle& style = ImGui::GetStyle();
    style.FramePadding = ImVec2(4.0f, 2.0f);
    style.ItemSpacing = ImVec2(8.0f, 3.0f);
    style.WindowRounding = 0.0f;
}

namespace {

/// Pads the sidebar's content down to where it ended in the last frame, as far as the window is
/// scrolled: a section that gets shorter (rows gone, a header folded, an error cleared) then never
/// makes ImGui pull the scroll back, which would move every control under the cursor
/// (docs/PREVIEW.md, "Panels"). Never past the last frame's end, so the wheel cannot scroll into
/// the padding, and the padding goes as the person scrolls up.
void hold_scroll(float& last_end) {
    const ImGuiStyle& style = ImGui::GetStyle();
    const float end = ImGui::GetCursorPosY();  // content coordinates: after the last item and its spacing
    // The end that keeps the scroll where it is: the content reaches the window's bottom edge
    // less its padding (plus a pixel for ImGui's rounding of the content size).
    const float holding_end = ImGui::GetScrollY() + ImGui::GetWindowHeight() - style.WindowPadding.y + style.ItemSpacing.y + 1.0f;
    const float target = std::min(last_end, holding_end);
    if (ImGui::GetScrollY() > 0.0f && target > end)
        ImGui::Dummy(ImVec2(0.0f, std::max(0.0f, target - end - style.ItemSpacing.y)));
    last_end = ImGui::GetCursorPosY();
}

/// The sections that show the scene's values: what differs, the knobs, the view, the statistics.
void draw_scene_value_sections(ViewModel& model, PanelState& state) {
    const std::size_t differing = model.differences().size();
    const std::string differs = "Differs from the scene (" + std::to_string(differing) + ")###differs";
    if (ImGui::CollapsingHeader(differs.c_str(), ImGuiTreeNodeFlags_DefaultOpen)) draw_differences_section(model);
    if (ImGui::CollapsingHeader("Light transport and caustics", ImGuiTreeNodeFlags_DefaultOpen)) draw_caustics_section(model, state);
    if (ImGui::CollapsingHeader("View and save")) draw_view_section(model, state);
    if (ImGui::CollapsingHeader("Statistics", ImGuiTreeNodeFlags_DefaultOpen)) draw_stats_section(model, state);
}

}  // namespace

void draw_sidebar(ViewModel& model, PanelState& state, glm::vec2 window) {
    ImGui::SetNextWindowPos(ImVec2(window.x - sidebar_width, 0.0f));
    ImGui::SetNextWindowSize(ImVec2(sidebar_width, window.y));
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                   ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings;
    ImGui::Begin("caustica preview", nullptr, flags);
    state.knob_rects.clear();  // only the knobs drawn in this frame
    ImGui::PushItemWidth(-150.0f);  // room for the labels on the right
    if (state.camera_text_scene != model.scene_path()) state.camera_text.clear();  // copied in another scene
    if (ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) draw_scene_section(model, state);
    // Until a scene has loaded there are no values to show: the panels' defaults would flash in
    // their place in the first frames.
    state.scene_values_shown = model.has_scene();
    if (state.scene_values_shown) draw_scene_value_sections(model, state);
    else ImGui::TextDisabled(model.loading() ? "loading the scene..." : "no scene loaded");
    hold_scroll(state.sidebar_content_end);
    ImGui::PopItemWidth();
    // Changes made while a widget is held (a slider dragged) are one undo step; set here too, so
    // that a folded section cannot leave it on.
    model.set_coalescing(ImGui::IsAnyItemActive());
    ImGui::End();
}

void show_message(PanelState& state, const std::string& text, bool sticky) {
    state.message = text;
    state.message_sticky = sticky;
    state.message_until = ImGui::GetTime() + (sticky ? 1e9 : 6.0);
}

void request_save(ViewModel& model, PanelState& state) {
    if (state.save_path[0] == '\0') {
        const std::string proposed = model.default_save_path();
        std::strncpy(state.save_path.data(), proposed.c_str(), state.save_path.size() - 1);
    }
    if (model.rendering()) {  // a partial image: ask whether now or once the render is done
        state.ask_save_choice = true;
        return;
    }
    save_now(model, state);
}

void save_now(ViewModel& model, PanelState& state) {
    const SaveResult result = model.save(state.save_path.data(), false);
    if (result.outcome == SaveOutcome::exists) {
        state.overwrite_when_done = false;
        state.ask_overwrite = true;
    } else {
        show_message(state, saved_message(model, result), result.outcome != SaveOutcome::written);
    }
}

void save_when_done(ViewModel& model, PanelState& state) {
    std::error_code ec;
    if (std::filesystem::exists(state.save_path.data(), ec)) {  // ask now, not when the render ends
        state.overwrite_when_done = true;
        state.ask_overwrite = true;
        return;
    }
    model.save_when_done(state.save_path.data(), false);
    show_message(state, std::string("will save ") + state.save_path.data() + " when the render is done");
}

std::string saved_message(const ViewModel& model, const SaveResult& result) {
    if (result.outcome != SaveOutcome::written || result.message.find(model.last_saved()) != std::string::npos)
        return result.message;  // save_preview_image names the absolute path itself
    return result.message + "\nfull path: " + model.last_saved();
}

}  // namespace caustica::ui
