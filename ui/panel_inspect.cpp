// The Inspect section, the hover readout and the sidebar toggle (ui/panel_inspect.h).
#include "ui/panel_inspect.h"

#include "ui/hover_readout.h"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

namespace caustica::ui {
namespace {

std::string percent(double fraction) {
    char text[32];
    std::snprintf(text, sizeof text, fraction > 0.0 && fraction < 0.001 ? "%.3f %%" : "%.1f %%", fraction * 100.0);
    return text;
}

// "scene.lua:12" of "/some/folder/scene.lua:12".
std::string short_where(const std::string& where) {
    const std::size_t slash = where.find_last_of('/');
    return slash == std::string::npos ? where : where.substr(slash + 1);
}

/// Labels under a strip `width` wide (the heat legend, the histogram), evenly spaced from its left
/// edge to its right, each kept within the strip.
void draw_axis_labels(float width, const char* const* labels, int count) {
    const float y = ImGui::GetCursorPosY();
    for (int i = 0; i < count; ++i) {
        const float w = ImGui::CalcTextSize(labels[i]).x;
        float x = width * static_cast<float>(i) / static_cast<float>(count - 1) - 0.5f * w;
        x = std::fmax(0.0f, std::fmin(x, width - w));
        ImGui::SetCursorPosX(ImGui::GetCursorStartPos().x + x);
        ImGui::SetCursorPosY(y);
        ImGui::TextUnformatted(labels[i]);
    }
}

/// The histogram of the displayed luminance with its axes: the fraction of pixels up to the
/// fullest bin, luminance on a log scale below.
void draw_histogram(const LuminanceHistogram& h) {
    const float fullest = *std::max_element(h.bins.begin(), h.bins.end());
    ImGui::TextDisabled("pixels per bin (top: %s of them)", percent(fullest).c_str());
    const float width = ImGui::GetContentRegionAvail().x;
    ImGui::PlotHistogram("##histogram", h.bins.data(), LuminanceHistogram::bin_count, 0, nullptr, 0.0f,
                         fullest > 0.0f ? fullest : 1.0f, ImVec2(width, 56.0f));
    const std::array<std::string, 4> labels = histogram_axis_labels();
    const char* const texts[4] = {labels[0].c_str(), labels[1].c_str(), labels[2].c_str(), labels[3].c_str()};
    draw_axis_labels(width, texts, 4);
    ImGui::TextDisabled("luminance after exposure, log scale (1 = white)");
}

}  // namespace

const char* compare_mode_name(CompareMode mode) {
    switch (mode) {
    case CompareMode::off: return "off";
    case CompareMode::split: return "split";
    case CompareMode::difference: return "difference";
    case CompareMode::heat: return "relative error";
    }
    return "?";
}

void draw_heat_legend(float width) {
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 at = ImGui::GetCursorScreenPos();
    const float height = 10.0f;
    const int steps = 48;
    for (int i = 0; i < steps; ++i) {
        const glm::vec3 c = heat_colour((static_cast<float>(i) + 0.5f) / steps);
        const float x0 = at.x + width * i / steps, x1 = at.x + width * (i + 1) / steps;
        draw->AddRectFilled(ImVec2(x0, at.y), ImVec2(x1 + 0.5f, at.y + height), ImGui::GetColorU32(ImVec4(c.r, c.g, c.b, 1.0f)));
    }
    ImGui::Dummy(ImVec2(width, height));
    // Labels at t = 0, 1/3, 2/3, 1: 0.1 %, 1 %, 10 %, 100 %.
    const char* const labels[4] = {"<=0.1%", "1%", "10%", ">=100%"};
    draw_axis_labels(width, labels, 4);
}

void draw_inspect_section(InspectState& state, const ViewModel& model) {
    const bool unfold = state.open_header;
    if (unfold) {
        ImGui::SetNextItemOpen(true);
        state.open_header = false;
    }
    if (!ImGui::CollapsingHeader("Inspect")) return;
    if (unfold) ImGui::SetScrollHereY(0.0f);  // the sidebar is longer than the window: show the section
    ImGui::PushItemWidth(-150.0f);
    // Histogram of the displayed luminance, log10 from 10^-4 to 10^2 (1 = white).
    const LuminanceHistogram& h = state.histogram;
    draw_histogram(h);
    ImGui::Text("clipped %s   black %s", percent(h.clipped).c_str(), percent(h.black).c_str());
    if (h.invalid > 0.0f) {
        ImGui::SameLine();
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "  NaN/inf %s", percent(h.invalid).c_str());
    }
    ImGui::Checkbox("readout at the cursor (Alt+I)", &state.readout);
    ImGui::SameLine();
    ImGui::TextDisabled("zoom %g%%", static_cast<double>(std::round(state.zoom.scale * 1000.0f) / 10.0f));

    ImGui::Separator();
    ImGui::TextUnformatted("A/B: current (A) against a reference (B)");
    if (ImGui::Button("Snapshot (Alt+B)")) state.snapshot_requested = true;
    ImGui::SameLine();
    if (ImGui::Button("Clear")) state.clear_requested = true;
    ImGui::InputText("##reference", state.reference_path.data(), state.reference_path.size());
    ImGui::SameLine();
    if (ImGui::Button("Load reference")) state.load_requested = true;
    int mode = static_cast<int>(state.mode);
    const char* modes[] = {"off", "split", "difference", "relative error"};
    if (ImGui::Combo("compare (Alt+A)", &mode, modes, 4)) state.mode = static_cast<CompareMode>(mode);
    const Image& image = model.driver().image();
    if (state.reference.width <= 0) {
        ImGui::TextDisabled("no reference: Snapshot or Load");
    } else {
        ImGui::Text("B: %s (%d x %d)", state.reference_name.c_str(), state.reference.width, state.reference.height);
        const std::string range = reference_range_note(state.reference_name);
        if (!range.empty()) {
            ImGui::PushTextWrapPos(0.0f);
            ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.3f, 1.0f), "%s", range.c_str());
            ImGui::PopTextWrapPos();
        }
        if (state.reference.width != image.width || state.reference.height != image.height)
            ImGui::TextColored(ImVec4(1.0f, 0.55f, 0.35f, 1.0f), "not compared: the image is %d x %d", image.width,
                               image.height);
    }
    if (!state.reference_problem.empty()) ImGui::TextColored(ImVec4(1.0f, 0.55f, 0.35f, 1.0f), "%s", state.reference_problem.c_str());
    if (state.mode == CompareMode::split) ImGui::SliderFloat("split", &state.split, 0.0f, 1.0f, "%.2f");
    if (state.mode == CompareMode::difference) ImGui::SliderFloat("gain (stops)", &state.difference_stops, 0.0f, 10.0f, "%.1f");
    if (state.mode == CompareMode::heat) draw_heat_legend(ImGui::GetContentRegionAvail().x);
    if (state.metrics) {
        if (state.metrics->samples == 0) {
            ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.3f, 1.0f), "no finite pixels to compare (%zu NaN/inf)",
                               state.metrics->non_finite);
        } else {
            ImGui::Text("RMSE %.4g   mean rel. error %s", state.metrics->rmse, percent(state.metrics->mean_relative).c_str());
            ImGui::Text("max |A-B| %.4g   (%zu px sampled)", state.metrics->max_abs, state.metrics->samples);
            if (state.metrics->non_finite > 0)
                ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.3f, 1.0f), "%zu NaN/inf px left out", state.metrics->non_finite);
        }
    }
    ImGui::PopItemWidth();
}

void draw_hover_readout(InspectState& state, const ImageLayout& layout, glm::vec2 area) {
    if (!state.readout || !state.hover || !state.pixel.valid) return;
    const PixelReadout& p = state.pixel;
    if (layout.scale >= 4.0f) {  // the pixel read, outlined when pixels are big enough to see
        const glm::vec2 lo = layout.to_window(glm::vec2(p.x, p.y)), hi = layout.to_window(glm::vec2(p.x + 1, p.y + 1));
        ImGui::GetBackgroundDrawList()->AddRect(ImVec2(lo.x - 1.0f, lo.y - 1.0f), ImVec2(hi.x + 1.0f, hi.y + 1.0f),
                                                IM_COL32(255, 60, 200, 255));
    }
    // Clear of the cursor and inside the image area (ui/hover_readout.h), by the box's size in the
    // last frame (it changes little from one pixel to the next).
    const glm::vec2 at = readout_position(*state.hover, state.readout_size, area);
    ImGui::SetNextWindowPos(ImVec2(at.x, at.y), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.8f);
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoInputs |
                                   ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav;
    ImGui::Begin("##readout", nullptr, flags);
    ImGui::Text("pixel %d, %d   zoom %g%%", p.x, p.y, static_cast<double>(std::round(layout.scale * 1000.0f) / 10.0f));
    ImGui::Text("RGB %s  (Y %.3g)", format_rgb(p.rgb).c_str(), static_cast<double>(luminance(p.rgb)));
    if (p.reference) {
        ImGui::Text("ref %s  rel. err %s", format_rgb(*p.reference).c_str(),
                    percent(relative_error(p.rgb, *p.reference, state.epsilon)).c_str());
    }
    if (const std::optional<SurfaceInspection>& s = state.surface) {
        ImGui::Text("object %s  %s", s->object.empty() ? "?" : s->object.c_str(), short_where(s->object_where).c_str());
        const char* kind = s->transparent ? "  glass" : s->reflective ? "  mirror" : "";
        if (s->material >= 0)
            ImGui::Text("material #%d  %s%s", s->material, short_where(s->material_where).c_str(), kind);
        else
            ImGui::Text("default material%s", kind);
        ImGui::Text("kd %s  ks %s", format_rgb(s->kd).c_str(), format_rgb(s->ks).c_str());
        if (s->caustic)
            ImGui::Text("caustic %s  (%s photons in map)", format_rgb(*s->caustic).c_str(),
                        std::to_string(s->map_photons).c_str());
        else
            ImGui::TextDisabled("caustic: no photon map");
        ImGui::TextDisabled("at %s, distance %.3g", format_rgb(s->point).c_str(), static_cast<double>(s->distance));
    } else {
        ImGui::TextDisabled("background (no surface)");
    }
    state.readout_size = glm::vec2(ImGui::GetWindowSize().x, ImGui::GetWindowSize().y);
    ImGui::End();
}

void draw_sidebar_toggle(InspectState& state, float area_right) {
    ImGui::SetNextWindowPos(ImVec2(area_right - 4.0f, 4.0f), ImGuiCond_Always, ImVec2(1.0f, 0.0f));
    ImGui::SetNextWindowBgAlpha(0.0f);
    const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                   ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoBackground;
    ImGui::Begin("##sidebar_toggle", nullptr, flags);
    if (ImGui::SmallButton(state.sidebar_hidden ? "<< show panels (Tab)" : "hide panels >> (Tab)")) state.sidebar_hidden = !state.sidebar_hidden;
    ImGui::End();
}

}  // namespace caustica::ui
