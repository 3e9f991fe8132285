// The View section: camera, display (exposure, tone curve, sRGB: shader only), resolution and threads, saving.
#include "ui/panels.h"
#include "ui/tooltip.h"

#include <imgui.h>

#include <cstring>
#include <filesystem>
#include <thread>

namespace caustica::ui {
namespace {

/// Named cameras of this scene: save the one shown, go to one, delete one.
void bookmarks(ViewModel& model, PanelState& state) {
    if (!ImGui::TreeNode("camera bookmarks")) return;
    const std::string scene = model.scene_path().empty()
                                  ? std::string()
                                  : std::filesystem::weakly_canonical(std::filesystem::absolute(model.scene_path())).string();
    ImGui::PushItemWidth(-90.0f);
    const bool entered = ImGui::InputTextWithHint("##bookmark", "name", state.bookmark_name.data(), state.bookmark_name.size(),
                                                  ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::PopItemWidth();
    ImGui::SameLine();
    ImGui::BeginDisabled(!model.has_scene());
    if ((ImGui::Button("Bookmark") || entered) && model.has_scene() &&
        model.bookmarks().set(scene, state.bookmark_name.data(), model.orbit_camera().desc()))
        state.bookmark_name[0] = '\0';
    ImGui::EndDisabled();
    for (const auto& [name, camera] : model.bookmarks().of(scene)) {
        ImGui::PushID(name.c_str());
        if (ImGui::SmallButton("go to")) model.go_to_camera(camera);
        ImGui::SameLine();
        const bool remove = ImGui::SmallButton("delete");
        ImGui::SameLine();
        ImGui::TextUnformatted(name.c_str());
        ImGui::PopID();
        if (remove) {
            model.bookmarks().remove(scene, name);
            break;  // the list changed under the loop
        }
    }
    if (!model.bookmarks().warning().empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.3f, 1.0f), "%s", model.bookmarks().warning().c_str());
        ImGui::PopTextWrapPos();
    }
    ImGui::TreePop();
}

/// The render region (docs/PREVIEW.md, "Render region") and its Clear button: one line whether a
/// region is set or not, so that nothing below it moves when one is drawn or cleared.
void render_region_row(ViewModel& model) {
    const RenderRegion& region = model.render_region();
    ImGui::BeginDisabled(region.empty());
    if (ImGui::SmallButton("Clear region")) model.clear_render_region();
    ImGui::EndDisabled();
    ImGui::SameLine();
    if (region.empty()) ImGui::TextDisabled("render region: none (Shift+drag on the image)");
    else ImGui::Text("render region %d,%d - %d,%d (%d x %d)", region.x0, region.y0, region.x1, region.y1,
                     region.width(), region.height());
    hint("Shift+drag (or Ctrl+B, then drag) a box on the image: every pass goes there alone, the rest keeps "
         "its image; Ctrl+Alt+B or Clear region renders the whole image again");
}

/// The view transform's curve: the job's --tonemap, or one the person picks (a saved PNG uses it).
void tone_curve_combo(ViewModel& model) {
    DisplaySettings& display = model.display();
    const ViewTransform shown = model.view_transform();
    if (ImGui::BeginCombo("tone curve", tonemap_name(shown.tonemap))) {
        for (Tonemap op : {Tonemap::clamp, Tonemap::reinhard, Tonemap::filmic})
            if (ImGui::Selectable(tonemap_name(op), op == shown.tonemap)) display.tonemap = op;
        ImGui::EndCombo();
    }
    hint("the --tonemap curve of a saved PNG, after the exposure (docs/OUTPUT.md): clamp (the original's), "
         "reinhard x/(1+x), filmic (ACES fit); EXR and PFM stay linear");
    ImGui::SameLine();
    ImGui::TextDisabled("%+.1f stops", shown.exposure_stops);
    hint("the job's --exposure plus the display's: what the viewport shows");
}

}  // namespace

void draw_view_section(ViewModel& model, PanelState& state) {
    const OrbitCamera& orbit = model.orbit_camera();
    const glm::dvec3 eye = orbit.eye(), target = orbit.target();
    ImGui::Text("eye    %8.3f %8.3f %8.3f", eye.x, eye.y, eye.z);
    ImGui::Text("target %8.3f %8.3f %8.3f", target.x, target.y, target.z);
    if (ImGui::Button("script camera (Home)")) model.reset_camera();
    ImGui::SameLine();
    if (ImGui::Button("Copy camera")) {
        state.camera_text = model.camera_text();
        state.camera_text_scene = model.scene_path();
        ImGui::SetClipboardText(state.camera_text.c_str());
    }
    hint("copies the camera shown as gr.render's eye, view, up and angle, to paste into the script "
         "(the command line has no camera option)");
    ImGui::SameLine();
    ImGui::TextDisabled(orbit.moved() ? "moved" : "as scripted");
    if (!state.camera_text.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled("copied: %s", state.camera_text.c_str());
        ImGui::PopTextWrapPos();
    }
    bookmarks(model, state);

    ImGui::Separator();
    DisplaySettings& display = model.display();
    ImGui::SliderFloat("exposure (E)", &display.exposure, -6.0f, 6.0f, "%+.1f stops");
    tone_curve_combo(model);
    ImGui::Checkbox("sRGB display (Alt+G)", &display.srgb);
    ImGui::SameLine();
    ImGui::TextDisabled("display only");

    ImGui::Separator();
    float scale = static_cast<float>(model.resolution_scale());
    if (ImGui::SliderFloat("resolution", &scale, 0.1f, 2.0f, "%.2fx", ImGuiSliderFlags_AlwaysClamp))
        model.set_resolution_scale(scale);
    int threads = model.threads();
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    if (ImGui::SliderInt("threads", &threads, 0, cores, threads == 0 ? "all" : "%d")) model.set_threads(threads);
    render_region_row(model);

    ImGui::Separator();
    if (state.save_path_scene != model.scene_path()) {  // propose the script's output name per scene
        const std::string proposed = model.default_save_path();
        std::strncpy(state.save_path.data(), proposed.c_str(), state.save_path.size() - 1);
        state.save_path_scene = model.scene_path();
    }
    ImGui::PushItemWidth(-60.0f);
    ImGui::InputText("##save", state.save_path.data(), state.save_path.size());
    ImGui::PopItemWidth();
    ImGui::SameLine();
    if (ImGui::Button("Save")) request_save(model, state);
    ImGui::TextDisabled("PNG, EXR or PFM by the extension: the current samples and the camera shown (Ctrl+S)");
    ImGui::Checkbox("PNG: apply the display exposure", &model.display().exposure_to_png);
    hint("off: the PNG holds what `caustica render` writes; on: the exposure above is added to the job's --exposure");
    if (!model.scheduled_save().empty()) {
        ImGui::TextDisabled("saves %s when the render is done", model.scheduled_save().c_str());
        ImGui::SameLine();
        if (ImGui::SmallButton("cancel")) model.cancel_scheduled_save();
    }
    if (!model.last_saved().empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled("last saved: %s", model.last_saved().c_str());
        ImGui::PopTextWrapPos();
    }
}

}  // namespace caustica::ui
