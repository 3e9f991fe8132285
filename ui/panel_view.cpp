// The View section: camera, display (exposure, sRGB: shader only), resolution and threads, saving.
#include "ui/panels.h"

#include <imgui.h>

#include <cstring>
#include <thread>

namespace caustica::ui {

void draw_view_section(ViewModel& model, PanelState& state) {
    const OrbitCamera& orbit = model.orbit_camera();
    const glm::dvec3 eye = orbit.eye(), target = orbit.target();
    ImGui::Text("eye    %8.3f %8.3f %8.3f", eye.x, eye.y, eye.z);
    ImGui::Text("target %8.3f %8.3f %8.3f", target.x, target.y, target.z);
    if (ImGui::Button("script camera (R)")) model.reset_camera();
    ImGui::SameLine();
    ImGui::TextDisabled(orbit.moved() ? "moved" : "as scripted");

    ImGui::Separator();
    DisplaySettings& display = model.display();
    ImGui::SliderFloat("exposure (E)", &display.exposure, -6.0f, 6.0f, "%+.1f stops");
    ImGui::Checkbox("sRGB display (G)", &display.srgb);
    ImGui::SameLine();
    ImGui::TextDisabled("display only");

    ImGui::Separator();
    float scale = static_cast<float>(model.resolution_scale());
    if (ImGui::SliderFloat("resolution", &scale, 0.1f, 2.0f, "%.2fx", ImGuiSliderFlags_AlwaysClamp))
        model.set_resolution_scale(scale);
    int threads = model.threads();
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    if (ImGui::SliderInt("threads", &threads, 0, cores, threads == 0 ? "all" : "%d")) model.set_threads(threads);

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
    ImGui::TextDisabled("PNG of the current samples (Ctrl+S)");
}

}  // namespace caustica::ui
