// What floats over the image area: the status line, a scene error, the help, the overwrite
// question and passing messages.
#include "ui/panels.h"
#include "ui/text_lines.h"

#include <imgui.h>

#include "ui/key_events.h"
#include "ui/keys.h"
#include "ui/render_region_tool.h"
#include "ui/shortcuts.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

namespace caustica::ui {
namespace {

constexpr ImGuiWindowFlags floating = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                      ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                      ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove;

/// " (shown x3)", " (shown at 50%)": how large the image is drawn, when not 1:1.
std::string magnification(float scale) {
    if (!(scale > 0.0f) || std::abs(scale - 1.0f) < 1e-3f) return {};
    char text[48];
    if (scale > 1.0f && std::abs(scale - std::round(scale)) < 1e-3f) std::snprintf(text, sizeof text, " (shown x%d)", int(std::lround(scale)));
    else std::snprintf(text, sizeof text, " (shown at %.0f%%)", 100.0 * scale);
    return text;
}

constexpr float overlay_margin = 8.0f;  // between the floating boxes and the image area's edges

/// The box of the current ImGui window: min x, min y, max x, max y.
glm::vec4 window_box() {
    const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    return {at.x, at.y, at.x + size.x, at.y + size.y};
}

/// The status line at the image area's top-left, its lines wrapped to the area's width less the
/// sidebar's toggle button at its top-right, so that it never runs under either.
void status_line(const ViewModel& model, PanelState& state, float scale, glm::vec2 area) {
    const float toggle = ImGui::CalcTextSize("hide panels >> (Tab)").x + 2.0f * ImGui::GetStyle().FramePadding.x + 8.0f;
    const float width = std::max(area.x - 2.0f * overlay_margin - toggle, 120.0f);
    ImGui::SetNextWindowPos(ImVec2(overlay_margin, overlay_margin));
    ImGui::SetNextWindowSizeConstraints(ImVec2(0.0f, 0.0f), ImVec2(width, area.y - 2.0f * overlay_margin));
    ImGui::SetNextWindowBgAlpha(0.55f);
    ImGui::Begin("##status", nullptr, floating | ImGuiWindowFlags_NoInputs);
    const float text_width = width - 2.0f * ImGui::GetStyle().WindowPadding.x;
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + text_width);
    const PreviewDriver& driver = model.driver();
    const SessionProgress& p = driver.progress();
    const std::string name = std::filesystem::path(model.scene_path()).filename().string();
    if (driver.has_job()) {
        const std::string what = render_state(model);
        if (driver.job().options.accumulates()) {  // passes without end: the percentage means nothing
            ImGui::Text("%s  %d x %d%s  %s  %.1f s", name.c_str(), driver.job().width, driver.job().height,
                        magnification(scale).c_str(), what.c_str(), p.elapsed_seconds);
            const SessionProgress& a = driver.accumulation();
            if (a.accumulating)
                for (const std::string& line :
                     lines_of_parts(refinement_parts(a), "  |  ", text_width,
                                    [](const std::string& t) { return ImGui::CalcTextSize(t.c_str()).x; }))
                    ImGui::TextUnformatted(line.c_str());
        } else {
            const double done = 100.0 * render_fraction(p);
            ImGui::Text("%s  %d x %d%s  %s %3.0f%%  %.2f s", name.c_str(), driver.job().width, driver.job().height,
                        magnification(scale).c_str(), what.c_str(), done, p.elapsed_seconds);
        }
        photon_progress_bar(p, std::min(320.0f, text_width));
        if (const std::string region = region_status(model.render_region()); !region.empty())
            ImGui::TextUnformatted(region.c_str());
    } else {
        ImGui::TextUnformatted(model.loading() ? "loading..." : "no scene");
    }
    if (model.loading() && driver.has_job()) ImGui::TextDisabled("loading %s...", name.c_str());
    ImGui::PopTextWrapPos();
    state.status_box = window_box();
    ImGui::End();
}

/// A scene error under the status line (both stay readable), as wide as the image area allows.
void error_banner(ViewModel& model, PanelState& state, glm::vec2 area) {
    state.error_box = glm::vec4(0.0f);
    if (model.error().empty()) return;
    const float top = std::max(state.status_box.w, 0.0f) + 6.0f, width = std::max(area.x - 2.0f * overlay_margin, 200.0f);
    ImGui::SetNextWindowPos(ImVec2(overlay_margin, top));
    ImGui::SetNextWindowSizeConstraints(ImVec2(200.0f, 0.0f), ImVec2(width, std::max(area.y - top - overlay_margin, 60.0f)));
    ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(0.45f, 0.05f, 0.05f, 0.92f));
    ImGui::Begin("##error", nullptr, floating);
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + width - 2.0f * ImGui::GetStyle().WindowPadding.x);
    ImGui::TextUnformatted(model.error().c_str());
    ImGui::TextDisabled(model.has_scene() ? "the previous scene stays on screen; fix the file and it reloads"
                                          : "no scene loaded; fix the file and it reloads");
    ImGui::PopTextWrapPos();
    if (ImGui::SmallButton("dismiss")) model.clear_error();
    state.error_box = window_box();
    ImGui::End();
    ImGui::PopStyleColor();
}

void help_window(PanelState& state, glm::vec2 area) {
    if (!state.show_help) return;
    ImGui::SetNextWindowPos(ImVec2(area.x * 0.5f, area.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::Begin("Keys and mouse (F1 closes)", &state.show_help,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoCollapse);
    static const std::vector<std::pair<std::string, std::string>> rows = shortcut_help_rows();
    if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg)) {
        for (const auto& row : rows) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(row.first.c_str());
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(row.second.c_str());
        }
        ImGui::EndTable();
    }
    ImGui::End();
}

/// Enter (either key) and Esc in a question: taps shorter than a frame count too (ui/key_events.h).
/// Keys count from the frame after a question opened: the Enter that answered the previous
/// question (save now -> the file exists) must not answer this one too.
bool keys_for_question(const PanelState& state) { return ImGui::GetFrameCount() > state.question_frame; }
bool enter_pressed(const PanelState& state) {
    return keys_for_question(state) && (key_events().pressed(keys::enter) || key_events().pressed(keys::keypad_enter));
}
bool escape_pressed(const PanelState& state) { return keys_for_question(state) && key_events().pressed(keys::escape); }

void overwrite_question(ViewModel& model, PanelState& state) {
    if (state.ask_overwrite) {
        ImGui::OpenPopup("Replace the file?");
        state.ask_overwrite = false;
        state.question_frame = ImGui::GetFrameCount();
    }
    if (!ImGui::BeginPopupModal("Replace the file?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
    ImGui::Text("%s exists. Replace it?", state.save_path.data());
    if (ImGui::Button("Replace (Enter)") || enter_pressed(state)) {
        if (state.overwrite_when_done) {
            model.save_when_done(state.save_path.data(), true);
            show_message(state, std::string("will replace ") + state.save_path.data() + " when the render is done");
        } else {
            const SaveResult result = model.save(state.save_path.data(), true);
            show_message(state, saved_message(model, result), result.outcome != SaveOutcome::written);
        }
        ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel (Esc)") || escape_pressed(state)) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
}

/// While a render is in progress, Save asks: the passes so far, or once the render is done.
void save_choice(ViewModel& model, PanelState& state) {
    if (state.ask_save_choice) {
        ImGui::OpenPopup("Save while rendering");
        state.ask_save_choice = false;
        state.question_frame = ImGui::GetFrameCount();
    }
    if (!ImGui::BeginPopupModal("Save while rendering", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
    ImGui::Text("The render of %s is in progress.", state.save_path.data());
    const std::string now = "Save now (" + model.passes_text() + ") (Enter)";
    if (ImGui::Button(now.c_str()) || enter_pressed(state)) {
        ImGui::CloseCurrentPopup();
        save_now(model, state);
    }
    ImGui::SameLine();
    const bool ends = model.render_ends();
    ImGui::BeginDisabled(!ends);
    if (ImGui::Button("Save when done")) {
        ImGui::CloseCurrentPopup();
        save_when_done(model, state);
    }
    ImGui::EndDisabled();
    ImGui::SameLine();
    if (ImGui::Button("Cancel (Esc)") || escape_pressed(state)) ImGui::CloseCurrentPopup();
    if (!ends)
        ImGui::TextDisabled("The progressive preview refines until paused: it is never done.\n"
                            "Set a pass or time limit (or pause) to save a finished image.");
    ImGui::EndPopup();
}

void message(ViewModel& model, PanelState& state, glm::vec2 area) {
    if (std::optional<SaveResult> scheduled = model.take_scheduled_result())
        show_message(state, saved_message(model, *scheduled), scheduled->outcome != SaveOutcome::written);
    if (std::optional<ModelNote> note = model.take_note()) show_message(state, note->text, note->problem);
    if (!model.scheduled_save().empty() && (state.message.empty() || ImGui::GetTime() > state.message_until))
        show_message(state, "will save " + model.scheduled_save() + " when the render is done");
    if (state.message.empty() || ImGui::GetTime() > state.message_until) return;
    ImGui::SetNextWindowPos(ImVec2(8.0f, area.y - 8.0f), ImGuiCond_Always, ImVec2(0.0f, 1.0f));
    ImGui::SetNextWindowBgAlpha(0.8f);
    ImGui::Begin("##message", nullptr, floating);
    ImGui::TextUnformatted(state.message.c_str());
    if (!model.scheduled_save().empty() && state.message.rfind("will ", 0) == 0) {
        if (ImGui::SmallButton("cancel the save")) {
            model.cancel_scheduled_save();
            state.message.clear();
        }
        ImGui::SameLine();
    }
    if (ImGui::SmallButton("dismiss")) state.message.clear();
    ImGui::End();
}

void empty_hint(const ViewModel& model, glm::vec2 area) {
    if (model.has_scene()) return;
    ImGui::SetNextWindowPos(ImVec2(area.x * 0.5f, area.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::Begin("##empty", nullptr, floating | ImGuiWindowFlags_NoInputs);
    ImGui::TextUnformatted(model.loading() ? "loading the scene..."
                                           : "Open a scene: type its path in the Scene panel, pick one of the\n"
                                             "scenes listed there, or drop a .lua file on this window.");
    ImGui::End();
}

}  // namespace

void draw_image_overlays(ViewModel& model, PanelState& state, const ImageLayout& layout, glm::vec2 window) {
    const glm::vec2 area(state.image_area_width > 0.0f ? state.image_area_width : window.x - sidebar_width, window.y);
    status_line(model, state, layout.scale, area);
    error_banner(model, state, area);
    empty_hint(model, area);
    message(model, state, area);
    help_window(state, area);
    save_choice(model, state);
    overwrite_question(model, state);
}

}  // namespace caustica::ui
