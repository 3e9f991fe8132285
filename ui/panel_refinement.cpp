// Progressive refinement in the panels: the one-line summary of the accumulation (passes,
// photons, samples per pixel, estimated error, radius), what the render is doing, the photon
// stage's progress bar, and the Pause/Resume button with the stopping rules.
#include "ui/panels.h"
#include "ui/tooltip.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

namespace caustica::ui {

std::string short_count(double n) {
    static const struct {
        double scale;
        const char* suffix;
    } units[] = {{1e9, "G"}, {1e6, "M"}, {1e3, "k"}};
    char text[32];
    for (const auto& u : units)
        if (n >= u.scale) {
            std::snprintf(text, sizeof text, "%.3g%s", n / u.scale, u.suffix);
            return text;
        }
    std::snprintf(text, sizeof text, "%.0f", n);
    return text;
}

std::vector<std::string> refinement_parts(const SessionProgress& a) {
    const std::string passes = a.pass_limit > 0 ? std::to_string(a.passes_done) + " of " + std::to_string(a.pass_limit)
                                                : std::to_string(a.passes_done);
    char error[96];
    if (a.error.known)
        std::snprintf(error, sizeof error, "est. error %.1f%% (noise %.1f%%, bias %.1f%%)", 100.0 * a.error.relative,
                      100.0 * a.error.noise, 100.0 * a.error.bias);
    else
        std::snprintf(error, sizeof error, "est. error after 2 passes");
    char samples[32], radius[32];
    std::snprintf(samples, sizeof samples, "%.0f spp", a.samples_per_pixel);
    std::snprintf(radius, sizeof radius, "radius %.3g", a.radius);
    return {passes + (a.passes_done == 1 && a.pass_limit == 0 ? " pass" : " passes"),
            short_count(a.photons_emitted) + " photons", samples, error, radius};
}

std::string refinement_summary(const SessionProgress& a) {
    std::string text;
    for (const std::string& part : refinement_parts(a)) text += (text.empty() ? "" : "  |  ") + part;
    return text;
}

std::string render_state(const ViewModel& model) {
    const PreviewDriver& driver = model.driver();
    const SessionProgress& p = driver.progress();
    if (model.paused()) return driver.busy() ? "pausing" : "paused";
    if (p.running) return running_stage(p);
    if (p.finished) {
        const SessionProgress& a = driver.accumulation();
        return a.accumulating && !a.stopped_by.empty() ? "stopped by " + stop_reason(a.stopped_by) : "done";
    }
    return p.cancelled ? "stopped" : "failed";
}

void photon_progress_bar(const SessionProgress& p, float width) {
    if (!p.running || p.stage != "shooting photons" || p.photons_total <= 0) return;
    const double done = static_cast<double>(p.photons_done), total = static_cast<double>(p.photons_total);
    const std::string caption = "photons " + short_count(done) + " of " + short_count(total);
    ImGui::ProgressBar(static_cast<float>(std::min(1.0, done / total)), ImVec2(width, 0.0f), caption.c_str());
}

void draw_refinement_controls(ViewModel& model, PanelState& state) {
    const PreviewDriver& driver = model.driver();
    const bool paused = model.paused();
    ImGui::BeginDisabled(!paused && !driver.busy());
    if (ImGui::Button(paused ? "Resume (Space)" : "Pause (Space)", ImVec2(120.0f, 0.0f))) model.set_paused(!paused);
    ImGui::EndDisabled();
    hint("Pause keeps the passes gathered so far; Resume continues from them. Moving the camera or "
         "changing a knob while paused renders the change.");
    ImGui::SameLine();
    ImGui::TextDisabled("%s", render_state(model).c_str());

    // Applied on Enter: each change continues the accumulation under the new rules. A value out of
    // the option's range is refused with the option's own message, never clamped.
    StopRules rules = model.stop_rules();
    const ImGuiInputTextFlags on_enter = ImGuiInputTextFlags_EnterReturnsTrue;
    auto check = [&](const char* option, const std::string& value) {
        try {
            Options probe;
            apply_option_tokens(probe, {std::string("--") + option, value});
            state.rules_error.clear();
            return true;
        } catch (const std::exception& e) {
            state.rules_error = e.what();
            return false;
        }
    };
    int passes = rules.passes;
    if (ImGui::InputInt("pass limit (0=none)", &passes, 1, 10, on_enter) && check("passes", std::to_string(passes)))
        rules.passes = passes;
    hint("stop after this many passes (0 = no limit); Enter applies. Never restarts the accumulation");
    double time_limit = rules.time_limit;
    if (ImGui::InputDouble("time limit (0=none)", &time_limit, 1.0, 10.0, "%.1f s", on_enter) &&
        check("time", exact_number(time_limit)))
        rules.time_limit = time_limit;
    hint("seconds of rendering after which no pass starts (0 = no limit); Enter applies");
    double percent = 100.0 * rules.target_error;
    if (ImGui::InputDouble("target error (0=none)", &percent, 0.5, 5.0, "%.2f %%", on_enter) &&
        check("target-error", exact_number(percent / 100.0)))
        rules.target_error = percent / 100.0;
    hint("stop once the estimated relative error over the caustics is below this (0 = none); Enter applies");
    if (!state.rules_error.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s (not applied)", state.rules_error.c_str());
        ImGui::PopTextWrapPos();
    }
    model.set_stop_rules(rules);
}

}  // namespace caustica::ui
