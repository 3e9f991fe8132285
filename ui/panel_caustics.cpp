// The Caustics section: live knobs of the photon map, the debug views and the overlay settings.
#include "ui/panels.h"
#include "ui/tooltip.h"

#include "core/integrators/registry.h"

#include "core/scene/source_location.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <type_traits>

namespace caustica::ui {
namespace {

void overlay_settings(ViewModel& model, PanelState& state) {
    OverlaySettings overlay = model.overlay();
    if (state.open_overlay_header) {
        ImGui::SetNextItemOpen(true);
        state.open_overlay_header = false;
    }
    if (!ImGui::TreeNodeEx("Projection-map overlay", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ImGui::Checkbox("outline (Alt+O)", &overlay.enabled);
    ImGui::SameLine();
    ImGui::Checkbox("occupied cells (Alt+C)", &overlay.cells);
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
/// The field sits right of its knob's drag field (typed_row_width) and carries the row's label.
constexpr float typed_width = 84.0f;

/// The width of the widget before a typed field, so that both fit where one item goes.
float typed_row_width() {
    return std::max(60.0f, ImGui::CalcItemWidth() - typed_width - ImGui::GetStyle().ItemInnerSpacing.x);
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
    if (state.type_into == label) {  // Ctrl+click on the knob's drag field
        ImGui::SetKeyboardFocusHere();
        state.type_into.clear();
    }
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

/// A number as `format` shows it ("%.4g").
std::string formatted(const char* format, double value) {
    char text[64];
    std::snprintf(text, sizeof text, format, value);
    return text;
}

/// The tooltip of a logarithmic knob: what it does, then how it is dragged and typed.
void drag_hint(const char* what) {
    if (!item_wants_tooltip()) return;
    char how[160];
    std::snprintf(how, sizeof how, "\ndrag: %.0f%% a pixel; Shift+drag: %.0f%% a pixel; Ctrl+click or the field on the "
                  "right: type a value", 100.0 * (fine_factor_per_pixel - 1.0), 100.0 * (coarse_factor_per_pixel - 1.0));
    wrapped_tooltip((std::string(what) + how).c_str());
}

/// A logarithmic knob's drag field, left of its typed field `label`: a drag changes the value by a
/// bounded factor a pixel (ui/knob_drag.h; Shift: coarse), a click alone changes nothing, and
/// Ctrl+click moves the keyboard to the typed field. Its rectangle goes to state.knob_rects.
bool log_drag(PanelState& state, const char* label, double& value, const LogKnobScale& scale, const std::string& text) {
    const ImGuiStyle& style = ImGui::GetStyle();
    ImGui::PushStyleColor(ImGuiCol_Button, style.Colors[ImGuiCol_FrameBg]);
    ImGui::PushStyleColor(ImGuiCol_ButtonHovered, style.Colors[ImGuiCol_FrameBgHovered]);
    ImGui::PushStyleColor(ImGuiCol_ButtonActive, style.Colors[ImGuiCol_FrameBgActive]);
    ImGui::Button((text + "###drag " + label).c_str(), ImVec2(typed_row_width(), 0.0f));
    ImGui::PopStyleColor(3);
    state.knob_rects[label] = {glm::vec2(ImGui::GetItemRectMin().x, ImGui::GetItemRectMin().y),
                               glm::vec2(ImGui::GetItemRectMax().x, ImGui::GetItemRectMax().y)};
    const ImGuiIO& io = ImGui::GetIO();
    if (ImGui::IsItemActivated()) {
        if (io.KeyCtrl) {
            state.type_into = label;
        } else {
            state.knob_drag.begin(value, io.MousePos.x, io.KeyShift);
            state.knob_dragged = label;
        }
    }
    bool changed = false;
    if (ImGui::IsItemActive() && state.knob_dragged == label) {
        const double dragged = state.knob_drag.update(scale, io.MousePos.x, io.KeyShift);
        changed = dragged != value;
        value = dragged;
    }
    if (ImGui::IsItemDeactivated() && state.knob_dragged == label) state.knob_dragged.clear();
    return changed;
}

/// The typed photon count's check beyond the option's range: what one light's photon map can hold
/// in this machine's memory (the photon knob's end).
std::function<std::string(const Options&)> memory_check(const char* option, long long Options::*count, long long limit) {
    return [option, count, limit](const Options& o) -> std::string {
        if (o.*count <= limit) return {};
        return std::string("--") + option + ": " + std::to_string(o.*count) + " is above the " + std::to_string(limit) +
               " photons a light's photon map can hold in this machine's memory";
    };
}

/// A logarithmic knob's row: what it is called, its option, its drag's range, how its value is
/// shown ("%.4g"; whole numbers as they are) and what it does (the tooltip).
struct KnobRow {
    const char* label;
    const char* option;
    LogKnobScale scale;
    const char* format;
    const char* what;
};

/// Draws a knob's drag field and its typed field, and applies either to `value` (typed: the
/// option's `field` as the option table reads it, checked by `extra` too).
template <typename T>
void knob_row(PanelState& state, const KnobRow& row, T& value, T Options::*field,
              const std::function<std::string(const Options&)>& extra = {}) {
    std::string shown, current;
    if constexpr (std::is_integral_v<T>) {
        current = std::to_string(value);
        shown = value == 0 && row.scale.zero ? "0 (off)" : current;
    } else {
        current = exact_number(value);
        shown = value == 0.0 && row.scale.zero ? "0 (off)" : formatted(row.format, value);
    }
    double dragged = static_cast<double>(value);
    if (log_drag(state, row.label, dragged, row.scale, shown)) {
        if constexpr (std::is_integral_v<T>) value = static_cast<T>(std::llround(dragged));
        else value = dragged;
    }
    drag_hint(row.what);
    Options typed;
    if (typed_option(state, row.label, row.option, current, extra, typed)) value = typed.*field;
}

/// The classic integrator's GI photon map: photons and neighbours, dragged or typed.
void gi_knobs(PanelState& state, CausticKnobs& k, const LogKnobScale& photon_scale, long long photons_limit) {
    knob_row(state,
             {"GI photons", "gi-num-photons", photon_scale, nullptr,
              "photons per light for the GI map, up to what this machine's memory holds; re-shoots photons"},
             k.gi_photons, &Options::gi_num_photons, memory_check("gi-num-photons", &Options::gi_num_photons, photons_limit));
    knob_row(state,
             {"GI neighbours", "gi-num-neighbours", {1.0, 1e6, false, true}, nullptr,
              "photons in each GI estimate (1 to a million); gathers again"},
             k.gi_neighbours, &Options::gi_num_neighbours);
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
    if (integrator_entry(k.integrator).accumulates && integrator_entry(model.knobs().integrator).accumulates) {
        draw_refinement_controls(model, state);
        // How the passes gather and shoot (docs/CAUSTICS.md, "Progressive photon mapping"): each
        // starts the accumulation again.
        knob_row(state,
                 {"first radius", "accumulation-radius", {0.1, 100.0}, "%.3g",
                  "the first gather radius in pixel footprints (shrinking pass by pass): smaller is sharper and "
                  "noisier; 1.5 suits thin or sharp-edged caustics, 3 smooth ones. Starts the accumulation again"},
                 k.first_radius, &Options::accumulation_radius);
        ImGui::Checkbox("balanced radius", &k.auto_radius);
        hint("--auto-radius: every radius scaled by one factor before passes 4, 8, 16, ... so that the estimate's "
             "blur and noise balance: one setting for thin and smooth caustics alike (start it from a first radius "
             "of 1.5). Starts the accumulation again");
        ImGui::SameLine();
        ImGui::Checkbox("radius per pixel", &k.adaptive_radius);
        hint("--adaptive-radius: each pixel's radius shrinks where its blur outweighs its noise (after 8, 32, "
             "128, ... passes); with a first radius of 1.5, the lowest error measured on sharp caustics. Starts "
             "the accumulation again");
        ImGui::Checkbox("guided emission", &k.guided_emission);
        hint("--guided-emission: after the first pass, more photons through the parts of the projection map "
             "whose photons lit what the image shows below white; the same image on average. Starts the "
             "accumulation again");
        knob_row(state,
                 {"radius alpha", "radius-alpha", {0.05, 1.0}, "%.3g",
                  "how slowly the gather radius shrinks pass by pass, r^2 <- r^2 (i + alpha) / (i + 1): smaller "
                  "shrinks faster (less blur, more noise late on); 1 keeps the first radius, converging to its "
                  "blur. Starts the accumulation again"},
                 k.radius_alpha, &Options::radius_alpha);
        knob_row(state,
                 {"photons per pixel", "photons-per-pixel", {0.01, 1000.0, true}, "%.3g",
                  "at least this many photons traced a pass per image pixel, shared by the lights (0: the photon "
                  "count below as given): ties the pass's photons to the image size. Re-shoots photons"},
                 k.photons_per_pixel, &Options::photons_per_pixel);
        ImGui::Checkbox("photon splitting", &k.photon_split);
        hint("--photon-split: at mirrors and glass, follow both the reflected and the refracted photon, each "
             "carrying its share, instead of choosing one by Russian roulette. Re-shoots photons");
    }

    // Photons: 0 to what the photon map can hold in memory, on a logarithmic scale.
    const long long photons_limit = photon_memory_limit();
    const LogKnobScale photon_scale{1000.0, static_cast<double>(photons_limit), true, true};
    knob_row(state,
             {"photons", "caustic-num-photons", photon_scale, nullptr,
              "photons per light over its whole sphere (0 = no caustics), up to what this machine's memory holds; "
              "re-shoots photons, keeps the BVH"},
             k.num_photons, &Options::caustic_num_photons,
             memory_check("caustic-num-photons", &Options::caustic_num_photons, photons_limit));
    knob_row(state,
             {"unit distance", "unit-distance", {1e-3, 1e4}, "%.4g",
              "the scene's unit of distance for photon energy; re-shoots photons"},
             k.unit_distance, &Options::unit_distance);
    // Accumulating passes gather within a radius, not N photons: N then serves a single pass only.
    Options shown_options;
    k.apply(shown_options);
    model.stop_rules().apply(shown_options);
    const bool gathers_by_radius = shown_options.accumulates();
    ImGui::BeginDisabled(gathers_by_radius);
    knob_row(state,
             {"neighbours N", "caustic-num-neighbours", {1.0, 1e6, false, true}, nullptr,
              "photons in each radiance estimate (1 to a million); gathers again, no new photons"},
             k.num_neighbours, &Options::caustic_num_neighbours);
    ImGui::EndDisabled();
    if (gathers_by_radius)
        hint("the progressive passes gather within the first radius above, shrinking, not N photons: N is "
             "used only when the stopping rules render a single pass",
             true);

    bool automatic = k.max_dist < 0.0;
    if (ImGui::Checkbox("auto max distance", &automatic)) k.max_dist = automatic ? -1.0 : 0.15 * k.unit_distance;
    hint("automatic: 0.15 x unit distance");
    if (!automatic) {
        knob_row(state,
                 {"max distance", "caustic-max-dist", {1e-4 * k.unit_distance, 100.0 * k.unit_distance}, "%.4g",
                  "largest photon gather radius (any positive value); gathers again, no new photons"},
                 k.max_dist, &Options::caustic_max_dist);
    } else {
        ImGui::SameLine();
        ImGui::TextDisabled("= %.4g", 0.15 * k.unit_distance);
    }
    knob_row(state, {"energy fudge", "energy-fudge", {0.01, 100.0}, "%.3g", "scales every photon's energy; re-shoots photons"},
             k.energy_fudge, &Options::energy_fudge);
    int mode = static_cast<int>(k.projection_map);
    if (ImGui::Combo("projection maps", &mode, "auto\0on\0off\0")) k.projection_map = static_cast<ProjectionMapMode>(mode);
    knob_row(state,
             {"map granularity", "caustic-pm-gran", {2.0, 4096.0, false, true}, nullptr,
              "rows of the polar map (columns: twice as many), 2 to 4096"},
             k.pm_granularity, &Options::caustic_pm_gran);
    ImGui::Checkbox("photons only", &k.photons_only);
    hint("show the caustic radiance estimate alone");
    ImGui::SameLine();
    ImGui::Checkbox("photon dots", &k.photon_dots);
    hint("show the stored photons as dots");
    if (ImGui::BeginCombo("show", shown_layer_name(k.layer))) {
        for (ShadingLayer layer : shown_layers)
            if (ImGui::Selectable(shown_layer_name(layer), layer == k.layer)) k.layer = layer;
        ImGui::EndCombo();
    }
    hint("one layer of the light as the image (--show-layer; docs/OUTPUT.md, Layers): direct, indirect, caustic "
         "and background add up to the image; albedo and normal are the first surface's. Alt+L: the next one");
    if (integrator_entry(k.integrator).gi_map) {
        ImGui::Checkbox("global illumination", &k.gi);
        hint("classic --gi: a GI photon map replaces the ambient term; re-shoots photons");
        if (k.gi) gi_knobs(state, k, photon_scale, photons_limit);
    }
    model.set_coalescing(ImGui::IsAnyItemActive());  // a drag is one undo step
    model.set_knobs(k);
    if (ImGui::SmallButton("script values")) model.reset_knobs();
    ImGui::SameLine();
    ImGui::TextDisabled("N, max distance: re-gather only");
    overlay_settings(model, state);
}

namespace {

/// The differences region's content: a row per difference, reset all, the command line.
void differences_rows(ViewModel& model) {
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
            if (!d.note.empty()) hint(d.note.c_str());
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

}  // namespace

void draw_differences_section(ViewModel& model) {
    // A region of fixed height, scrolling inside: rows that come and go with each change never
    // move the knobs below it (docs/PREVIEW.md, "Panels").
    ImGui::BeginChild("differences region", ImVec2(0.0f, differences_region_lines * ImGui::GetTextLineHeightWithSpacing()));
    differences_rows(model);
    ImGui::EndChild();
}

}  // namespace caustica::ui
