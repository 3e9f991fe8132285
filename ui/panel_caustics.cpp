// The Caustics section: live knobs of the photon map, the debug views and the overlay settings.
#include "ui/panels.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

namespace caustica::ui {
namespace {

bool slider_double(const char* label, double& value, double lo, double hi, const char* format) {
    return ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &lo, &hi, format,
                               ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
}

void hint(const char* text) {
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

void overlay_settings(ViewModel& model, PanelState& state) {
    OverlaySettings overlay = model.overlay();
    if (state.open_overlay_header) {
        ImGui::SetNextItemOpen(true);
        state.open_overlay_header = false;
    }
    if (!ImGui::TreeNodeEx("Projection-map overlay", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ImGui::Checkbox("outline (O)", &overlay.enabled);
    ImGui::SameLine();
    ImGui::Checkbox("occupied cells (C)", &overlay.cells);
    const std::vector<LightProjectionMap>& maps = model.driver().projection_maps();
    if (maps.size() > 1) {
        overlay.light = std::clamp(overlay.light, 0, static_cast<int>(maps.size()) - 1);
        char label[64];
        std::snprintf(label, sizeof label, "light %d", maps[overlay.light].light_index + 1);
        if (ImGui::BeginCombo("light", label)) {
            for (int i = 0; i < static_cast<int>(maps.size()); ++i) {
                std::snprintf(label, sizeof label, "light %d", maps[i].light_index + 1);
                if (ImGui::Selectable(label, i == overlay.light)) overlay.light = i;
            }
            ImGui::EndCombo();
        }
    }
    const std::string note = model.overlay_note();
    if (!note.empty()) ImGui::TextWrapped("%s", note.c_str());
    model.set_overlay(overlay);
    ImGui::TreePop();
}

}  // namespace

void draw_caustics_section(ViewModel& model, PanelState& state) {
    CausticKnobs k = model.knobs();
    int integrator = static_cast<int>(k.integrator);
    if (ImGui::Combo("integrator", &integrator, "classic\0progressive\0"))
        k.integrator = static_cast<IntegratorKind>(integrator);
    hint("classic: the original renderer's rules (SEED_BEHAVIOUR.md Part B); progressive: our photon mapper, "
         "refining pass after pass until paused or a stopping rule. Switching re-shoots photons and re-renders, "
         "keeps the BVH");
    if (k.integrator == IntegratorKind::progressive && model.knobs().integrator == IntegratorKind::progressive)
        draw_refinement_controls(model);
    const long long photons_lo = 0, photons_hi = 5'000'000;
    ImGui::SliderScalar("photons", ImGuiDataType_S64, &k.num_photons, &photons_lo, &photons_hi, "%lld",
                        ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
    hint("photons per light over its whole sphere (0 = no caustics); re-shoots photons, keeps the BVH");
    slider_double("unit distance", k.unit_distance, 1e-3, 1e4, "%.4g");
    hint("the scene's unit of distance for photon energy; re-shoots photons");
    ImGui::SliderInt("neighbours N", &k.num_neighbours, 1, 1000, "%d", ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
    hint("photons in each radiance estimate; gathers again, no new photons");
    bool automatic = k.max_dist < 0.0;
    if (ImGui::Checkbox("auto max distance", &automatic)) k.max_dist = automatic ? -1.0 : 0.15 * k.unit_distance;
    hint("automatic: 0.15 x unit distance");
    if (!automatic) {
        slider_double("max distance", k.max_dist, 1e-4 * k.unit_distance, 10.0 * k.unit_distance, "%.4g");
        hint("largest photon gather radius; gathers again, no new photons");
    } else {
        ImGui::SameLine();
        ImGui::TextDisabled("= %.4g", 0.15 * k.unit_distance);
    }
    slider_double("energy fudge", k.energy_fudge, 0.01, 100.0, "%.3g");
    hint("scales every photon's energy; re-shoots photons");
    int mode = static_cast<int>(k.projection_map);
    if (ImGui::Combo("projection maps", &mode, "auto\0on\0off\0")) k.projection_map = static_cast<ProjectionMapMode>(mode);
    ImGui::SliderInt("map granularity", &k.pm_granularity, 8, 720, "%d", ImGuiSliderFlags_AlwaysClamp);
    hint("rows of the polar map (columns: twice as many)");
    ImGui::Checkbox("photons only", &k.photons_only);
    hint("show the caustic radiance estimate alone");
    ImGui::SameLine();
    ImGui::Checkbox("photon dots", &k.photon_dots);
    hint("show the stored photons as dots");
    if (k.integrator == IntegratorKind::classic) {
        ImGui::Checkbox("global illumination", &k.gi);
        hint("classic --gi: a GI photon map replaces the ambient term; re-shoots photons");
        if (k.gi) {
            const long long gi_lo = 1000, gi_hi = 10'000'000;
            ImGui::SliderScalar("GI photons", ImGuiDataType_S64, &k.gi_photons, &gi_lo, &gi_hi, "%lld",
                                ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
            ImGui::SliderInt("GI neighbours", &k.gi_neighbours, 1, 1000, "%d",
                             ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
        }
    }
    model.set_knobs(k);
    if (ImGui::SmallButton("script values")) model.reset_knobs();
    ImGui::SameLine();
    ImGui::TextDisabled("N, max distance: re-gather only");
    overlay_settings(model, state);
}

}  // namespace caustica::ui
