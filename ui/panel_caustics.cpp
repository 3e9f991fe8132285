// The Caustics section: live knobs of the photon map, the debug views and the overlay settings.
#include "ui/panels.h"

#include "core/integrators/registry.h"

#include "core/scene/source_location.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

namespace caustica::ui {
namespace {

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

/// A typed value of an option, checked by the option table itself (its ranges and messages) and
/// by `extra` (e.g. the memory limit); applied on Enter only when valid, otherwise the error stays
/// next to the field and nothing changes: never clamped silently.
/// The field sits right of its slider (begin_typed_row) and carries the row's label.
constexpr float typed_width = 84.0f;

/// Sets the width of the slider before a typed field, so that both fit where one item goes.
void begin_typed_row() {
    ImGui::SetNextItemWidth(std::max(60.0f, ImGui::CalcItemWidth() - typed_width - ImGui::GetStyle().ItemInnerSpacing.x));
}

bool typed_option(PanelState& state, const char* label, const char* option, const std::string& current,
                  const std::function<std::string(const Options&)>& extra, Options& parsed) {
    PanelState::TypedField& field = state.typed[label];
    if (!field.error.empty() && !field.editing && current != field.error_value) field.error.clear();  // changed since
    if (!field.editing) {
        std::snprintf(field.text.data(), field.text.size(), "%s", current.c_str());
    }
    ImGui::SameLine(0.0f, ImGui::GetStyle().ItemInnerSpacing.x);
    ImGui::SetNextItemWidth(typed_width);
    const bool entered = ImGui::InputText(label, field.text.data(), field.text.size(),
                                          ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
    field.editing = ImGui::IsItemActive();
    hint("type a value and press Enter; any value the option accepts on the command line");
    bool applied = false;
    if (entered) {
        field.editing = false;
        try {
            Options probe;
            apply_option_tokens(probe, {std::string("--") + option, field.text.data()});
            const std::string problem = extra ? extra(probe) : std::string();
            if (!problem.empty()) throw InputError(problem);
            parsed = probe;
            field.error.clear();
            applied = true;
        } catch (const std::exception& e) {
            field.error = e.what();
            field.error_value = current;
            field.editing = true;  // keep the typed text to correct it
        }
    }
    if (!field.error.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s (not applied)", field.error.c_str());
        ImGui::PopTextWrapPos();
    }
    return applied;
}

/// A logarithmic slider over [lo, hi], widened to hold the current value (a click on it never
/// silently moves a value that lies outside to the slider's end).
bool log_slider(const char* label, double& value, double lo, double hi, const char* format, bool typed = false) {
    if (value > 0.0) lo = std::min(lo, value), hi = std::max(hi, value);
    if (typed) begin_typed_row();
    return ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &lo, &hi, format,
                               ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_NoInput);
}

}  // namespace

void draw_caustics_section(ViewModel& model, PanelState& state) {
    ImGui::BeginDisabled(!model.can_undo());
    if (ImGui::SmallButton("Undo (Ctrl+Z)")) model.undo();
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(!model.can_redo());
    if (ImGui::SmallButton("Redo (Ctrl+Shift+Z)")) model.redo();
    ImGui::EndDisabled();

    int preset = 0;
    for (int i = 0; i < 4; ++i)
        if (model.preset() == quality_preset_names[i]) preset = i;
    if (ImGui::Combo("quality preset", &preset, "scene's values\0draft\0preview\0final\0"))
        model.set_preset(quality_preset_names[preset]);
    hint("--quality: photons, N, max distance, anti-aliasing and shadow grid of docs/ACCURACY.md, applied over "
         "the scene's options (the knobs below win over it). scene's values (no --quality): exactly what "
         "`caustica render SCENE` uses");

    CausticKnobs k = model.knobs();
    if (ImGui::BeginCombo("integrator", integrator_entry(k.integrator).name)) {
        for (const IntegratorEntry& entry : integrator_entries())
            if (ImGui::Selectable(entry.name, entry.kind == k.integrator)) k.integrator = entry.kind;
        ImGui::EndCombo();
    }
    hint("classic: the original renderer's rules (docs/CAUSTICS.md, rule by rule); progressive: our photon mapper, "
         "refining pass after pass until paused or a stopping rule. Switching re-shoots photons and re-renders, "
         "keeps the BVH. Your pick is kept for this scene: it opens with it next time (a --integrator given for "
         "it on the command line wins; the reset under Differs from the scene forgets it)");
    if (integrator_entry(k.integrator).accumulates && integrator_entry(model.knobs().integrator).accumulates)
        draw_refinement_controls(model, state);

    // Photons: 0 to what the photon map can hold in memory, on a logarithmic scale.
    const long long photons_limit = photon_memory_limit();
    const long long photons_lo = 0, photons_hi = std::max(photons_limit, k.num_photons);
    begin_typed_row();
    ImGui::SliderScalar("##photons", ImGuiDataType_S64, &k.num_photons, &photons_lo, &photons_hi,
                        k.num_photons == 0 ? "0 (off)" : "%lld", ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_NoInput);
    hint("photons per light over its whole sphere (0 = no caustics), up to what this machine's memory holds; "
         "re-shoots photons, keeps the BVH");
    Options typed;
    auto memory_check = [photons_limit](const Options& o) -> std::string {
        if (o.caustic_num_photons <= photons_limit) return {};
        return "--caustic-num-photons: " + std::to_string(o.caustic_num_photons) + " is above the " +
               std::to_string(photons_limit) + " photons a light's photon map can hold in this machine's memory";
    };
    if (typed_option(state, "photons", "caustic-num-photons", std::to_string(k.num_photons), memory_check, typed))
        k.num_photons = typed.caustic_num_photons;

    double unit = k.unit_distance;
    if (log_slider("##unit", unit, 1e-3, 1e4, "%.4g", true)) k.unit_distance = unit;
    hint("the scene's unit of distance for photon energy; re-shoots photons");
    if (typed_option(state, "unit distance", "unit-distance", exact_number(k.unit_distance), {}, typed))
        k.unit_distance = typed.unit_distance;

    double neighbours = k.num_neighbours;
    if (log_slider("##neighbours", neighbours, 1.0, 1e6, "%.0f", true))
        k.num_neighbours = static_cast<int>(std::clamp(std::lround(neighbours), 1L, 1'000'000L));
    hint("photons in each radiance estimate (1 to a million); gathers again, no new photons");
    if (typed_option(state, "neighbours N", "caustic-num-neighbours", std::to_string(k.num_neighbours), {}, typed))
        k.num_neighbours = typed.caustic_num_neighbours;

    bool automatic = k.max_dist < 0.0;
    if (ImGui::Checkbox("auto max distance", &automatic)) k.max_dist = automatic ? -1.0 : 0.15 * k.unit_distance;
    hint("automatic: 0.15 x unit distance");
    if (!automatic) {
        log_slider("##max_dist", k.max_dist, 1e-4 * k.unit_distance, 100.0 * k.unit_distance, "%.4g", true);
        hint("largest photon gather radius (any positive value); gathers again, no new photons");
        if (typed_option(state, "max distance", "caustic-max-dist", exact_number(k.max_dist), {}, typed))
            k.max_dist = typed.caustic_max_dist;
    } else {
        ImGui::SameLine();
        ImGui::TextDisabled("= %.4g", 0.15 * k.unit_distance);
    }
    log_slider("energy fudge", k.energy_fudge, 0.01, 100.0, "%.3g");
    hint("scales every photon's energy; re-shoots photons");
    int mode = static_cast<int>(k.projection_map);
    if (ImGui::Combo("projection maps", &mode, "auto\0on\0off\0")) k.projection_map = static_cast<ProjectionMapMode>(mode);
    ImGui::SliderInt("map granularity", &k.pm_granularity, 2, 4096, "%d", ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_NoInput);
    hint("rows of the polar map (columns: twice as many), 2 to 4096");
    ImGui::Checkbox("photons only", &k.photons_only);
    hint("show the caustic radiance estimate alone");
    ImGui::SameLine();
    ImGui::Checkbox("photon dots", &k.photon_dots);
    hint("show the stored photons as dots");
    if (integrator_entry(k.integrator).gi_map) {
        ImGui::Checkbox("global illumination", &k.gi);
        hint("classic --gi: a GI photon map replaces the ambient term; re-shoots photons");
        if (k.gi) {
            const long long gi_lo = 0, gi_hi = std::max(photons_limit, k.gi_photons);
            ImGui::SliderScalar("GI photons", ImGuiDataType_S64, &k.gi_photons, &gi_lo, &gi_hi, "%lld",
                                ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_NoInput);
            ImGui::SliderInt("GI neighbours", &k.gi_neighbours, 1, 1'000'000, "%d",
                             ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_NoInput);
        }
    }
    model.set_coalescing(ImGui::IsAnyItemActive());  // a drag is one undo step
    model.set_knobs(k);
    if (ImGui::SmallButton("script values")) model.reset_knobs();
    ImGui::SameLine();
    ImGui::TextDisabled("N, max distance: re-gather only");
    overlay_settings(model, state);
}

void draw_differences_section(ViewModel& model) {
    if (!model.has_scene()) {  // nothing shown: nothing differs, no command renders it
        ImGui::TextDisabled("no scene loaded");
        return;
    }
    const std::vector<Difference> differences = model.differences();
    if (differences.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled("none: the preview renders what `caustica render` renders");
        ImGui::PopTextWrapPos();
    } else if (ImGui::BeginTable("differences", 3, ImGuiTableFlags_SizingFixedFit)) {
        ImGui::TableSetupColumn("what", ImGuiTableColumnFlags_WidthFixed, 110.0f);
        ImGui::TableSetupColumn("values", ImGuiTableColumnFlags_WidthStretch);
        ImGui::TableSetupColumn("reset", ImGuiTableColumnFlags_WidthFixed, 40.0f);
        for (const Difference& d : differences) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(d.label.c_str());
            ImGui::TableNextColumn();
            ImGui::TextWrapped("%s -> %s", d.scene.c_str(), d.shown.c_str());
            if (!d.note.empty() && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", d.note.c_str());
            ImGui::TableNextColumn();
            ImGui::PushID(d.id.c_str());
            if (ImGui::SmallButton("reset")) model.reset_difference(d.id);
            ImGui::PopID();
        }
        ImGui::EndTable();
        if (ImGui::SmallButton("reset all")) model.reset_difference("all");
        hint("back to the scene's values (the camera stays: R resets it)");
        ImGui::SameLine();
    }
    if (ImGui::SmallButton("Copy command line")) ImGui::SetClipboardText(model.command_line().c_str());
    hint("copies the `caustica render` command that renders the image shown");
    std::string text = model.command_line();
    if (!text.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextDisabled("%s", text.c_str());
        for (const std::string& note : model.command_line_notes()) ImGui::TextDisabled("note: %s", note.c_str());
        ImGui::PopTextWrapPos();
    }
}

}  // namespace caustica::ui
