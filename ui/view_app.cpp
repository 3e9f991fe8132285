#include "ui/view_app.h"

#include "ui/camera_input.h"
#include "ui/key_events.h"
#include "ui/keys.h"
#include "ui/shortcuts.h"

#include "core/scene/camera.h"

#include <imgui.h>

#if __has_include("core/io/image_io.h")
#include "core/io/image_io.h"
#define CAUSTICA_HAS_IMAGE_IO 1
#else
#include "core/io/png_io.h"
#endif

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>

namespace caustica::ui {
namespace {

constexpr float split_grab_pixels = 6.0f;  // how near the split line a press grabs it

double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

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
    const bool over_area = !io.WantCaptureMouse && mouse.x >= 0.0f && mouse.y >= 0.0f && mouse.x < area_.x &&
                           mouse.y < window.y;
    const bool split_shown = inspect_.mode == CompareMode::split && image_->reference_matches();
    const float split_x = layout_.origin.x + inspect_.split * layout_.size().x;
    for (int b = 0; b < 3; ++b) {
        if (ImGui::IsMouseClicked(b) && over_area) {  // a drag belongs to where it began
            if (b == 0 && region_drag_.takes_press(io.KeyShift)) region_drag_.begin(layout_.to_image(mouse));
            else if (b == 0 && io.KeyCtrl) panning_image_ = true;  // Ctrl+drag moves the zoomed image
            else if (b == 0 && split_shown && std::abs(mouse.x - split_x) <= split_grab_pixels) dragging_split_ = true;
            else dragging_[b] = true;
        }
        if (!io.MouseDown[b]) {
            dragging_[b] = false;
            if (b == 0) panning_image_ = dragging_split_ = false;
            if (b == 0 && region_drag_.active) {  // released: the box becomes the region (a click: none drawn)
                region_drag_.active = false;
                const Image& image = model_.driver().image();
                if (const RenderRegion region = region_drag_.region(image.width, image.height); !region.empty())
                    model_.set_render_region(region);
            }
        }
    }
    const glm::vec2 delta(io.MouseDelta.x, io.MouseDelta.y);
    const bool moved = (delta.x != 0.0f || delta.y != 0.0f) && io.MousePos.x > -1e30f && io.MousePosPrev.x > -1e30f;
    if (moved && region_drag_.active) region_drag_.to = layout_.to_image(mouse);
    if (moved && dragging_[0]) {
        const glm::dvec2 degrees = drag_orbit(delta);
        model_.orbit(degrees.x, degrees.y);
    }
    if (moved && (dragging_[1] || dragging_[2])) model_.pan(glm::dvec2(delta) / static_cast<double>(layout_.scale));
    if (moved && panning_image_) inspect_.zoom.pan(layout_, glm::vec2(0.0f), area_, delta);
    if (moved && dragging_split_ && layout_.image_width > 0)
        inspect_.split = std::clamp(layout_.to_image(mouse).x / static_cast<float>(layout_.image_width), 0.0f, 1.0f);
    if (over_area && io.MouseWheel != 0.0f) {
        if (io.KeyCtrl) inspect_.zoom.zoom_at(layout_, glm::vec2(0.0f), area_, mouse, io.MouseWheel > 0.0f ? 1 : -1);
        else model_.zoom(io.MouseWheel);  // the camera dollies; Ctrl+wheel zooms the image
    }
    if (over_area && ImGui::IsMouseDoubleClicked(0) && layout_.contains(mouse)) {
        if (!model_.set_target_at(layout_.to_image(mouse))) show_message(state_, "nothing under the cursor");
    }
    const bool dragging =
        dragging_[0] || dragging_[1] || dragging_[2] || panning_image_ || dragging_split_ || region_drag_.active;
    // The readout follows a mouse that has moved: a pointer resting where the window opened
    // (Xvfb puts it at the screen's centre) shows nothing. It waits until the mouse and the camera
    // rest (ui/hover_readout.h), so it never covers the view being orbited to.
    if (moved) mouse_moved_ = true;
    const bool buttons_held = io.MouseDown[0] || io.MouseDown[1] || io.MouseDown[2];
    hover_rest_.update(ImGui::GetTime(), moved || dragging || buttons_held);
    inspect_.hover.reset();
    if (forced_hover_) inspect_.hover = forced_hover_;
    else if (mouse_moved_ && over_area && layout_.contains(mouse) && hover_rest_.resting(ImGui::GetTime()))
        inspect_.hover = mouse;
}

void ViewApp::note_camera_change() {
    // An orbit by the keys or a change of the view that the mouse did not make counts as activity
    // for the hover readout too.
    const OrbitCamera& orbit = model_.orbit_camera();
    const bool changed = orbit.eye() != shown_eye_ || orbit.target() != shown_target_;
    shown_eye_ = orbit.eye();
    shown_target_ = orbit.target();
    if (changed) hover_rest_.update(ImGui::GetTime(), true);
}

void ViewApp::handle_keys() {
    // Typing never acts, and nothing acts while a widget has the keyboard (ui/shortcuts.h): a text
    // field keeps its own undo, and letters typed after a missed click change nothing.
    const ImGuiIO& io = ImGui::GetIO();
    const bool keyboard_taken = io.WantTextInput || io.WantCaptureKeyboard || ImGui::IsAnyItemActive();
    OverlaySettings overlay = model_.overlay();
    CausticKnobs knobs = model_.knobs();
    float& exposure = model_.display().exposure;
    // The arrows move the camera as --orbit YAW,PITCH does (ui/camera_input.h).
    auto orbit_by = [&](int arrow) {
        const glm::dvec2 degrees = *arrow_orbit(arrow);
        model_.orbit(degrees.x, degrees.y);
    };
    for (Shortcut action : shortcuts_pressed(key_events(), keyboard_taken)) {
        switch (action) {
        case Shortcut::help: state_.show_help = !state_.show_help; break;
        case Shortcut::close_help: state_.show_help = false; break;
        case Shortcut::script_camera: model_.reset_camera(); break;
        case Shortcut::reload: model_.reload(); break;
        case Shortcut::pause: model_.set_paused(!model_.paused()); break;
        case Shortcut::outline: overlay.enabled = !overlay.enabled; break;
        case Shortcut::cells: overlay.cells = !overlay.cells; break;
        case Shortcut::photons_only: knobs.photons_only = !knobs.photons_only; break;
        case Shortcut::next_layer: knobs.layer = next_shown_layer(knobs.layer); break;
        case Shortcut::photon_dots: knobs.photon_dots = !knobs.photon_dots; break;
        case Shortcut::exposure_up: exposure = std::min(exposure + 1.0f, 6.0f); break;
        case Shortcut::exposure_down: exposure = std::max(exposure - 1.0f, -6.0f); break;
        case Shortcut::exposure_reset: exposure = 0.0f; break;
        case Shortcut::srgb: model_.display().srgb = !model_.display().srgb; break;
        case Shortcut::orbit_left: orbit_by(keys::left); break;
        case Shortcut::orbit_right: orbit_by(keys::right); break;
        case Shortcut::orbit_up: orbit_by(keys::up); break;
        case Shortcut::orbit_down: orbit_by(keys::down); break;
        case Shortcut::zoom_in: model_.zoom(1.0); break;
        case Shortcut::zoom_out: model_.zoom(-1.0); break;
        case Shortcut::toggle_panels: inspect_.sidebar_hidden = !inspect_.sidebar_hidden; break;
        case Shortcut::fit_image: inspect_.zoom.fit_area(); break;
        case Shortcut::image_one_to_one: {
            const glm::vec2 mouse(io.MousePos.x, io.MousePos.y);
            const glm::vec2 at = layout_.contains(mouse) ? mouse : 0.5f * area_;
            inspect_.zoom.set_scale(layout_, glm::vec2(0.0f), area_, at, 1.0f);
            break;
        }
        case Shortcut::snapshot: inspect_.snapshot_requested = true; break;
        case Shortcut::compare:
            inspect_.mode = static_cast<CompareMode>((static_cast<int>(inspect_.mode) + 1) % 4);
            break;
        case Shortcut::readout: inspect_.readout = !inspect_.readout; break;
        case Shortcut::save: request_save(model_, state_); break;
        case Shortcut::quit: quit_ = true; break;
        case Shortcut::undo: model_.undo(); break;
        case Shortcut::redo: model_.redo(); break;
        }
    }
    model_.set_overlay(overlay);
    if (!(knobs == model_.knobs())) model_.set_knobs(knobs);
}

void ViewApp::handle_region_keys() {
    // Ctrl+B arms the next left drag to draw the render region, as Blender's Cycles does; Ctrl+Alt+B
    // clears it; Esc disarms (docs/PREVIEW.md, "Render region"). Not while a widget has the keyboard.
    const ImGuiIO& io = ImGui::GetIO();
    if (io.WantTextInput || io.WantCaptureKeyboard || ImGui::IsAnyItemActive()) return;
    if (key_pressed_with(keys::b, key_mods::ctrl)) {
        region_drag_.armed = !region_drag_.armed;
        if (region_drag_.armed) show_message(state_, "render region: drag a box on the image (Esc cancels)");
    }
    if (key_pressed_with(keys::b, key_mods::ctrl | key_mods::alt)) {
        region_drag_.armed = false;
        model_.clear_render_region();
    }
    if (region_drag_.armed && key_pressed(keys::escape)) region_drag_.armed = false;
}

void ViewApp::draw_region_outline() const {
    // Over the image, under every window: the region the passes go to, and the box being drawn.
    const Image& image = model_.driver().image();
    const RenderRegion region = region_drag_.active ? region_drag_.region(image.width, image.height)
                                                    : model_.render_region();
    if (region.empty() || layout_.image_width <= 0) return;
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    draw->PushClipRect(ImVec2(0.0f, 0.0f), ImVec2(area_.x, area_.y), true);
    const glm::vec2 low = layout_.to_window(glm::vec2(region.x0, region.y0));
    const glm::vec2 high = layout_.to_window(glm::vec2(region.x1, region.y1));
    const ImU32 colour = region_drag_.active ? IM_COL32(255, 255, 255, 220) : IM_COL32(255, 190, 40, 230);
    // Outside the pixels by one screen pixel, so that the outline never covers the region's own.
    draw->AddRect(ImVec2(low.x - 1.0f, low.y - 1.0f), ImVec2(high.x + 1.0f, high.y + 1.0f), IM_COL32(0, 0, 0, 160),
                  0.0f, 0, 3.0f);
    draw->AddRect(ImVec2(low.x - 1.0f, low.y - 1.0f), ImVec2(high.x + 1.0f, high.y + 1.0f), colour, 0.0f, 0, 1.0f);
    draw->PopClipRect();
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

void ViewApp::load_reference() {
    const std::string path = inspect_.reference_path.data();
    if (path.empty()) {
        inspect_.reference_problem = "type the path of a PNG, EXR or PFM image to compare with";
        return;
    }
    try {
#ifdef CAUSTICA_HAS_IMAGE_IO
        Image image = read_image_file(path);
#else
        // Until core/io/image_io.h exists: PNG only, 8-bit values / 255 as linear (as the batch PNG).
        const Png8 png = read_png(path);
        Image image(png.width, png.height);
        for (int y = 0; y < png.height; ++y)
            for (int x = 0; x < png.width; ++x) {
                const unsigned char* p = &png.data[(static_cast<std::size_t>(y) * png.width + x) * png.channels];
                const bool grey = png.channels < 3;
                image.at(x, y) = glm::vec3(p[0], p[grey ? 0 : 1], p[grey ? 0 : 2]) / 255.0f;
            }
#endif
        inspect_.reference = std::move(image);
        inspect_.reference_name = std::filesystem::path(path).filename().string();
        ++inspect_.reference_version;
        inspect_.reference_problem.clear();
        if (inspect_.mode == CompareMode::off) inspect_.mode = CompareMode::split;
    } catch (const std::exception& e) {
        inspect_.reference_problem = e.what();  // the reader names the file and what is wrong
    }
}

void ViewApp::update_inspection() {
    const PreviewDriver& driver = model_.driver();
    const Image& image = driver.image();
    if (inspect_.snapshot_requested && image.width > 0) {
        inspect_.reference = image;
        inspect_.reference_name = "snapshot";
        ++inspect_.reference_version;
        inspect_.reference_problem.clear();
        if (inspect_.mode == CompareMode::off) inspect_.mode = CompareMode::split;
    }
    if (inspect_.load_requested) load_reference();
    if (inspect_.clear_requested) {
        inspect_.reference = Image();
        inspect_.reference_name.clear();
        ++inspect_.reference_version;
        inspect_.reference_problem.clear();
    }
    inspect_.snapshot_requested = inspect_.load_requested = inspect_.clear_requested = false;
    if (uploaded_reference_ != inspect_.reference_version) {
        image_->set_reference(inspect_.reference);
        uploaded_reference_ = inspect_.reference_version;
        inspect_.stats_due = true;
    }
    // The histogram and the metrics: when the image or the exposure changed, at most 4 times a
    // second, on a grid of at most 32768 pixels (0.75 ms at 1280 x 720).
    if (!driver.changed_tiles().empty() || driver.size_changed() || model_.view_transform().exposure_stops != stats_exposure_)
        inspect_.stats_due = true;
    const double now = now_seconds();
    if (inspect_.stats_due && now - inspect_.stats_at >= stats_interval) {
        const auto t0 = std::chrono::steady_clock::now();
        const int stride = sample_stride(image.width, image.height);
        stats_exposure_ = model_.view_transform().exposure_stops;
        inspect_.histogram = luminance_histogram(image, std::exp2(stats_exposure_), stride);
        inspect_.metrics = inspect_.reference.width > 0
                               ? compare_images(image, inspect_.reference, inspect_.epsilon, stride)
                               : std::nullopt;
        inspect_.stats_at = now;
        inspect_.stats_due = false;
        inspect_.stats_ms = std::chrono::duration<float, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
    // The readout: the pixel every frame (its value changes as the render refines), the surface
    // (one ray and one photon query) only when the pixel, the render or the photon map changes.
    inspect_.pixel = inspect_.hover ? read_pixel(image, layout_.to_image(*inspect_.hover), &inspect_.reference)
                                    : PixelReadout{};
    if (!inspect_.pixel.valid || !driver.has_job()) {
        inspect_.inspected = glm::ivec2(-1);
        inspect_.surface.reset();
        return;
    }
    const glm::ivec2 at(inspect_.pixel.x, inspect_.pixel.y);
    if (at == inspect_.inspected && driver.generation() == inspect_.inspected_generation &&
        driver.maps_version() == inspect_.inspected_maps)
        return;
    const RenderJob& job = driver.job();
    if (job.width != image.width || job.height != image.height) return;  // a resize on its way
    const Camera camera(job.camera, job.width, job.height);
    inspect_.surface = driver.session().inspect(camera.generate(at.x + 0.5f, at.y + 0.5f), job.options);
    inspect_.inspected = at;
    inspect_.inspected_generation = driver.generation();
    inspect_.inspected_maps = driver.maps_version();
}

void ViewApp::frame(glm::vec2 window) {
    const auto t0 = std::chrono::steady_clock::now();
    area_ = glm::vec2(std::max(window.x - (inspect_.sidebar_hidden ? 0.0f : sidebar_width), 1.0f), window.y);
    handle_mouse(window);
    handle_keys();
    handle_region_keys();
    note_camera_change();
    if (!forced_hover_ && !hover_rest_.resting(ImGui::GetTime())) inspect_.hover.reset();  // a key orbited
    area_ = glm::vec2(std::max(window.x - (inspect_.sidebar_hidden ? 0.0f : sidebar_width), 1.0f), window.y);
    model_.update();
    image_->upload(model_.driver());
    const Image& image = model_.driver().image();
    inspect_.zoom.clamp(image.width, image.height);
    layout_ = inspect_.zoom.layout(glm::vec2(0.0f), area_, image.width, image.height);
    if (inspect_.zoom.fit) inspect_.zoom.scale = layout_.scale;  // what the panel and the next step start from
    update_inspection();
    update_overlay_triangles();
    state_.image_area_width = area_.x;  // the banner and messages centre on the image area
    if (!inspect_.sidebar_hidden) {
        draw_sidebar(model_, state_, window);
        ImGui::Begin("caustica preview");  // appends the Inspect section to the sidebar window
        draw_inspect_section(inspect_, model_);
        ImGui::End();
    }
    draw_sidebar_toggle(inspect_, area_.x);
    if (inspect_.mode == CompareMode::split && image_->reference_matches() && layout_.image_width > 0) {
        // The split line, over the image but under every window.
        const float x = std::floor(layout_.origin.x + inspect_.split * layout_.size().x) + 0.5f;
        const float top = std::max(layout_.origin.y, 0.0f), bottom = std::min(layout_.origin.y + layout_.size().y, area_.y);
        if (x >= 0.0f && x < area_.x) {
            ImDrawList* draw = ImGui::GetBackgroundDrawList();
            draw->AddLine(ImVec2(x, top), ImVec2(x, bottom), IM_COL32(255, 255, 255, 200), 1.0f);
            draw->AddText(ImVec2(x - 18.0f, top + 4.0f), IM_COL32(255, 255, 255, 230), "A");
            draw->AddText(ImVec2(x + 10.0f, top + 4.0f), IM_COL32(255, 255, 255, 230), "B");
        }
    }
    draw_region_outline();
    draw_image_overlays(model_, state_, layout_, window);
    draw_hover_readout(inspect_, layout_, area_);
    state_.ui_frame_ms = std::chrono::duration<float, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void ViewApp::draw(glm::vec2 window, int framebuffer_width, int framebuffer_height) const {
    glViewport(0, 0, framebuffer_width, framebuffer_height);
    glClearColor(0.1f, 0.1f, 0.11f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    const glm::vec2 pixel_scale(framebuffer_width / std::max(1.0f, window.x), framebuffer_height / std::max(1.0f, window.y));
    // The image area in framebuffer pixels (origin at the bottom-left): a zoomed image stays in it.
    const glm::ivec4 area(0, static_cast<int>(std::floor((window.y - area_.y) * pixel_scale.y)),
                          static_cast<int>(std::ceil(area_.x * pixel_scale.x)),
                          static_cast<int>(std::ceil(area_.y * pixel_scale.y)));
    ImageView::Compare compare;
    compare.mode = static_cast<int>(inspect_.mode);
    compare.split = inspect_.split;
    compare.gain = std::exp2(inspect_.difference_stops);
    compare.epsilon = inspect_.epsilon;
    image_->draw(layout_, window, model_.view_transform(), compare, area);
    if (model_.overlay().enabled) overlay_->draw(layout_, window, pixel_scale, area);
}

}  // namespace caustica::ui
