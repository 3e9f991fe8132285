#include "ui/view_app.h"

#include "ui/keys.h"

#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

namespace caustica::ui {
namespace {

constexpr double degrees_per_pixel = 0.3;
constexpr double arrow_degrees = 5.0;

bool pressed(int key, bool repeat = false) { return ImGui::IsKeyPressed(key, repeat); }

}  // namespace

ViewApp::ViewApp(ViewModel& model)
    : model_(model), image_(std::make_unique<ImageView>()), overlay_(std::make_unique<OverlayRenderer>()) {}

ViewApp::~ViewApp() = default;

bool ViewApp::idle() const {
    return !model_.loading() && !model_.driver().busy() && !model_.driver().pending() && model_.overlay_settled();
}

void ViewApp::drop(const std::vector<std::string>& paths) {
    for (const std::string& p : paths)
        if (std::filesystem::path(p).extension() == ".lua") {
            model_.open(p);
            return;
        }
    if (!paths.empty()) show_message(state_, "not a scene script (.lua): " + paths.front());
}

void ViewApp::handle_mouse(glm::vec2 window) {
    const ImGuiIO& io = ImGui::GetIO();
    const glm::vec2 mouse(io.MousePos.x, io.MousePos.y);
    const bool over_area = !io.WantCaptureMouse && mouse.x >= 0.0f && mouse.y >= 0.0f &&
                           mouse.x < window.x - sidebar_width && mouse.y < window.y;
    for (int b = 0; b < 3; ++b) {
        if (ImGui::IsMouseClicked(b) && over_area) dragging_[b] = true;  // a drag belongs to where it began
        if (!io.MouseDown[b]) dragging_[b] = false;
    }
    const glm::vec2 delta(io.MouseDelta.x, io.MouseDelta.y);
    const bool moved = (delta.x != 0.0f || delta.y != 0.0f) && io.MousePos.x > -1e30f && io.MousePosPrev.x > -1e30f;
    if (moved && dragging_[0]) model_.orbit(-delta.x * degrees_per_pixel, delta.y * degrees_per_pixel);
    if (moved && (dragging_[1] || dragging_[2])) model_.pan(glm::dvec2(delta) / static_cast<double>(layout_.scale));
    if (over_area && io.MouseWheel != 0.0f) model_.zoom(io.MouseWheel);
    if (over_area && ImGui::IsMouseDoubleClicked(0) && layout_.contains(mouse)) {
        if (!model_.set_target_at(layout_.to_image(mouse))) show_message(state_, "nothing under the cursor");
    }
}

void ViewApp::handle_keys() {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.KeyCtrl && pressed(keys::s)) request_save(model_, state_);
    if (io.KeyCtrl && pressed(keys::q)) quit_ = true;  // Ctrl+Q
    if (io.WantCaptureKeyboard || io.KeyCtrl) {
        if (io.KeyCtrl && pressed(keys::e)) model_.display().exposure = 0.0f;
        return;
    }
    if (pressed(keys::f1) || pressed(keys::h)) state_.show_help = !state_.show_help;
    if (pressed(keys::escape)) state_.show_help = false;
    if (pressed(keys::r) || pressed(keys::home)) model_.reset_camera();
    if (pressed(keys::f5)) model_.reload();
    if (pressed(keys::space)) model_.set_paused(!model_.paused());
    OverlaySettings overlay = model_.overlay();
    if (pressed(keys::o)) overlay.enabled = !overlay.enabled;
    if (pressed(keys::c)) overlay.cells = !overlay.cells;
    model_.set_overlay(overlay);
    CausticKnobs knobs = model_.knobs();
    if (pressed(keys::p)) knobs.photons_only = !knobs.photons_only;
    if (pressed(keys::d)) knobs.photon_dots = !knobs.photon_dots;
    model_.set_knobs(knobs);
    if (pressed(keys::e))
        model_.display().exposure = std::clamp(model_.display().exposure + (io.KeyShift ? -1.0f : 1.0f), -6.0f, 6.0f);
    if (pressed(keys::g)) model_.display().srgb = !model_.display().srgb;
    if (pressed(keys::left, true)) model_.orbit(arrow_degrees, 0.0);
    if (pressed(keys::right, true)) model_.orbit(-arrow_degrees, 0.0);
    if (pressed(keys::up, true)) model_.orbit(0.0, -arrow_degrees);
    if (pressed(keys::down, true)) model_.orbit(0.0, arrow_degrees);
    if (pressed(keys::equal, true) || pressed(keys::keypad_add, true)) model_.zoom(1.0);
    if (pressed(keys::minus, true) || pressed(keys::keypad_subtract, true)) model_.zoom(-1.0);
}

void ViewApp::update_overlay_triangles() {
    if (!model_.overlay().enabled) return;
    if (model_.overlay_version() == overlay_version_ && layout_.scale == overlay_scale_) return;
    OverlayStyle style;  // constant sizes on screen, whatever the magnification
    style.line_width = 2.0f / layout_.scale;
    style.cell_size = 3.0f / layout_.scale;
    overlay_->set_triangles(overlay_triangles(model_.overlay_image(), style));
    overlay_version_ = model_.overlay_version();
    overlay_scale_ = layout_.scale;
}

void ViewApp::frame(glm::vec2 window) {
    const auto t0 = std::chrono::steady_clock::now();
    handle_mouse(window);
    handle_keys();
    model_.update();
    image_->upload(model_.driver());
    const Image& image = model_.driver().image();
    layout_ = fit_image(glm::vec2(0.0f), glm::vec2(window.x - sidebar_width, window.y), image.width, image.height);
    update_overlay_triangles();
    draw_sidebar(model_, state_, window);
    draw_image_overlays(model_, state_, layout_, window);
    state_.ui_frame_ms = std::chrono::duration<float, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void ViewApp::draw(glm::vec2 window, int framebuffer_width, int framebuffer_height) const {
    glViewport(0, 0, framebuffer_width, framebuffer_height);
    glClearColor(0.1f, 0.1f, 0.11f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    image_->draw(layout_, window, model_.display());
    const glm::vec2 pixel_scale(framebuffer_width / std::max(1.0f, window.x), framebuffer_height / std::max(1.0f, window.y));
    if (model_.overlay().enabled) overlay_->draw(layout_, window, pixel_scale);
}

}  // namespace caustica::ui
