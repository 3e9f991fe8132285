// The Statistics section: photons, stage times, passes, samples per pixel, rays/s, a pass plot.
#include "ui/panels.h"

#include "core/integrators/registry.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <vector>

namespace caustica::ui {
namespace {

const StageTime* find_stage(const std::vector<StageTime>& stages, const char* name) {
    for (const StageTime& s : stages)
        if (s.name == name) return &s;
    return nullptr;
}

/// One row of the stage table: the last real computation, and whether this render reused it.
void stage_row(const PreviewDriver& driver, const char* label, const char* name) {
    const StageTime* computed = find_stage(driver.computed_stages(), name);
    const StageTime* now = find_stage(driver.stats().stages, name);
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(label);
    ImGui::TableNextColumn();
    // Only stages this render has: a scene without photons shows no photon times of another one.
    if (computed && now) ImGui::Text("%9.1f ms", 1e3 * computed->seconds);
    else ImGui::TextDisabled("-");
    ImGui::TableNextColumn();
    if (now && now->cached) ImGui::TextDisabled("cached");
}

}  // namespace

void draw_stats_section(const ViewModel& model, const PanelState& state) {
    const PreviewDriver& driver = model.driver();
    const RenderStats& stats = driver.stats();
    const SessionProgress& p = driver.progress();
    ImGui::Text("integrator: %s", integrator_entry(model.knobs().integrator).name);

    for (std::size_t l = 0; l < stats.caustic_lights.size(); ++l) {
        const LightCausticStats& c = stats.caustic_lights[l];
        if (c.candidates == 0) continue;
        // The photons knob counts directions; only those the projection map keeps are traced, and
        // only photons that reach a diffuse surface after a specular one are stored.
        ImGui::Text("light %zu: %s of %s traced, %s stored", l + 1, short_count(double(c.traced)).c_str(),
                    short_count(double(c.candidates)).c_str(), short_count(double(c.stored)).c_str());
        if (c.projection_map_used)
            ImGui::TextDisabled("  (%.1f%% of directions in the projection map)", 100.0 * c.occupied_fraction);
    }
    if (stats.caustic_photons > 0) {
        ImGui::Text("photon map: %zu photons, %.1f MiB", stats.caustic_photons, stats.caustic_map_bytes / 1048576.0);
    } else {
        const std::string why = model.photons_note();
        if (why.empty()) ImGui::TextDisabled("no caustic photons");
        else {
            ImGui::PushTextWrapPos(0.0f);
            ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.3f, 1.0f), "%s", why.c_str());
            ImGui::PopTextWrapPos();
        }
    }

    if (ImGui::BeginTable("stages", 3)) {
        ImGui::TableSetupColumn("stage", ImGuiTableColumnFlags_WidthStretch);
        ImGui::TableSetupColumn("time", ImGuiTableColumnFlags_WidthFixed, 90.0f);
        ImGui::TableSetupColumn("reuse", ImGuiTableColumnFlags_WidthFixed, 50.0f);
        stage_row(driver, "scene + BVH", "scene build");
        stage_row(driver, "projection maps", "projection maps");
        stage_row(driver, "photon shooting", "photon shooting");
        stage_row(driver, "photon k-d tree", "photon k-d tree");
        ImGui::EndTable();
    }
    const double render_thread_seconds = stats.total_seconds * std::max(1, stats.threads);
    if (stats.rays.gathers > 0 && render_thread_seconds > 0.0)
        ImGui::Text("radiance estimates: %.0f%% of render time", 100.0 * stats.rays.gather_seconds / render_thread_seconds);

    const double pixels = std::max(1.0, static_cast<double>(driver.job().width) * driver.job().height);
    double pass_seconds = 0.0;
    for (const StageTime& s : stats.stages)
        if (s.name == "preview" || s.name == "first samples" || s.name == "anti-aliasing" ||
            s.name == "progressive passes")
            pass_seconds += s.seconds;
    const SessionProgress& a = driver.accumulation();
    if (driver.job().options.accumulates()) {
        ImGui::Text("%s: %d passes%s", render_state(model).c_str(), a.passes_done,
                    a.pass_limit > 0 ? (" of " + std::to_string(a.pass_limit)).c_str() : ", no limit");
        if (a.accumulating) {
            ImGui::Text("%.0f samples/pixel, %s photons, radius %.3g", a.samples_per_pixel,
                        short_count(static_cast<double>(a.photons_emitted)).c_str(), a.radius);
            if (a.error.known)
                ImGui::Text("estimated error %.2f%%: noise %.2f%%, bias %.2f%%", 100.0 * a.error.relative,
                            100.0 * a.error.noise, 100.0 * a.error.bias);
            else
                ImGui::TextDisabled("estimated error: known after 2 passes");
        }
    } else {
        ImGui::Text("pass %d of %d: %s", std::min(p.pass + 1, std::max(1, p.passes)), std::max(1, p.passes),
                    p.running ? (p.stage.empty() ? "starting" : p.stage.c_str())
                              : (p.finished ? "done" : p.cancelled ? "cancelled" : "-"));
    }
    if (stats.rays.samples > 0)
        ImGui::Text("%.2f samples/pixel, %.2f M rays/s", stats.rays.samples / pixels,
                    pass_seconds > 0.0 ? stats.rays.total_rays() / pass_seconds * 1e-6 : 0.0);

    std::vector<float> times;
    for (const PassTime& t : driver.pass_history()) times.push_back(static_cast<float>(1e3 * t.seconds));
    if (times.size() > 120) times.erase(times.begin(), times.end() - 120);
    if (!times.empty()) {
        char caption[64];
        std::snprintf(caption, sizeof caption, "last pass %.0f ms", times.back());
        ImGui::PlotHistogram("##passes", times.data(), static_cast<int>(times.size()), 0, caption, 0.0f,
                             *std::max_element(times.begin(), times.end()) * 1.1f,
                             ImVec2(ImGui::GetContentRegionAvail().x, 48.0f));
    }
    // The frame rate only means something while frames are being made for a render or a change.
    if (driver.busy() || model.changes_pending() || model.loading())
        ImGui::TextDisabled("UI %.0f fps (model and panels %.1f ms a frame)", ImGui::GetIO().Framerate, state.ui_frame_ms);
    else
        ImGui::TextDisabled("UI idle (model and panels %.1f ms a frame)", state.ui_frame_ms);
    ImGui::TextDisabled("%zu renders started, longest restart %.1f ms", static_cast<std::size_t>(driver.restarts()),
                        1e3 * driver.longest_restart_seconds());
}

}  // namespace caustica::ui
