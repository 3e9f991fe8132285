// The Scene section: open by path, from the scene folder or the recent list; choose the render.
#include "ui/panels.h"
#include "ui/tooltip.h"

#include <imgui.h>

#include <algorithm>
#include <cstring>
#include <filesystem>

namespace caustica::ui {
namespace {

void set_field(std::array<char, 1024>& field, const std::string& text) {
    std::strncpy(field.data(), text.c_str(), field.size() - 1);
    field[field.size() - 1] = '\0';
}

/// A list of paths; opens the one clicked.
void scene_list(ViewModel& model, PanelState& state, const char* id, const std::vector<std::string>& paths, int rows) {
    const float height = ImGui::GetTextLineHeightWithSpacing() * static_cast<float>(std::min<int>(rows, std::max<int>(1, paths.size()))) + 6.0f;
    if (!ImGui::BeginListBox(id, ImVec2(-1.0f, height))) return;
    for (const std::string& path : paths) {
        const bool current = path == model.scene_path();
        if (ImGui::Selectable(path.c_str(), current)) {
            set_field(state.open_path, path);
            model.open(path);
        }
    }
    ImGui::EndListBox();
}

/// The options of this scene: those given on the command line for it (later scenes start from
/// their own gr.option calls), and --a4 per scene with a hint for course scenes rendered without.
void scene_options(ViewModel& model) {
    std::string tokens;
    for (const std::string& t : model.scene_tokens())
        if (t != "--a4") tokens += (tokens.empty() ? "" : " ") + t;
    if (!tokens.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled("options for this scene: %s (from the command line)", tokens.c_str());
        ImGui::PopTextWrapPos();
    }
    const std::string origin = model.a4_origin();
    bool a4 = !origin.empty();
    const bool scripted = origin.rfind("gr.option", 0) == 0 || origin == "the script";
    ImGui::BeginDisabled(scripted);
    if (ImGui::Checkbox("--a4 course conventions", &a4)) model.set_a4(a4);
    ImGui::EndDisabled();
    hint("CS488 A4 conventions for this scene only: transforms act in the order written, gr.cube is the unit cube "
         "[0,1]^3. Rebuilds the scene",
         true);
    if (!origin.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled("  --a4 from %s", origin.c_str());
        ImGui::PopTextWrapPos();
    }
    if (!model.a4_hint().empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "%s", model.a4_hint().c_str());
        ImGui::PopTextWrapPos();
    }
}

}  // namespace

void draw_scene_section(ViewModel& model, PanelState& state) {
    if (state.open_path[0] == '\0' && !model.scene_path().empty()) set_field(state.open_path, model.scene_path());
    ImGui::PushItemWidth(-60.0f);
    const bool entered = ImGui::InputText("##path", state.open_path.data(), state.open_path.size(),
                                          ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::PopItemWidth();
    ImGui::SameLine();
    if ((ImGui::Button("Open") || entered) && state.open_path[0] != '\0') model.open(state.open_path.data());
    if (model.loading()) {
        ImGui::SameLine();
        ImGui::TextDisabled("loading...");
    }

    const double now = ImGui::GetTime();
    // Listed again every two seconds, and at once when another scene is shown: its folder is
    // listed too (the first frames run before the first scene has loaded).
    static std::string listed_for;
    if (now - state.scene_files_at > 2.0 || listed_for != model.scene_path()) {
        listed_for = model.scene_path();
        state.scene_files = model.source().scene_files(model.scene_path());
        state.scene_files_at = now;
    }
    ImGui::TextDisabled("scenes: click to open, or drop a .lua file");
    scene_list(model, state, "##scenes", state.scene_files, 4);
    if (!model.source().recent().empty() && ImGui::BeginCombo("recent scenes", "open a recent scene...")) {
        for (const std::string& path : model.source().recent())
            if (ImGui::Selectable(path.c_str(), path == model.scene_path())) {
                set_field(state.open_path, path);
                model.open(path);
            }
        ImGui::EndCombo();
    }
    if (!model.source().warning().empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.3f, 1.0f), "%s", model.source().warning().c_str());
        ImGui::PopTextWrapPos();
    }
    if (model.render_count() > 1) {
        int index = model.render_index() + 1;
        if (ImGui::SliderInt("gr.render call", &index, 1, model.render_count())) model.select_render(index - 1);
    }
    if (model.has_scene()) scene_options(model);
    const std::vector<std::string> warnings = model.warnings();
    if (!warnings.empty() && ImGui::TreeNode("warnings", "%zu warning%s", warnings.size(), warnings.size() == 1 ? "" : "s")) {
        for (const std::string& w : warnings) ImGui::TextWrapped("%s", w.c_str());
        ImGui::TreePop();
    }
}

}  // namespace caustica::ui
