// One frame of the preview, the same in the window and headless: mouse and keys (read from
// ImGui's io, which the platform fills) become model actions, the model advances, new tiles go
// to the texture, and the panels are built; then the image and overlay are drawn.
#pragma once

#include "ui/hover_readout.h"
#include "ui/image_layout.h"
#include "ui/image_view.h"
#include "ui/overlay_renderer.h"
#include "ui/panel_inspect.h"
#include "ui/panels.h"
#include "ui/render_region_tool.h"
#include "ui/view_model.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace caustica::ui {

/// The preview application on a current GL context with an ImGui context.
class ViewApp {
public:
    /// Creates the GL objects (shaders, texture) on the current context.
    explicit ViewApp(ViewModel& model);
    ~ViewApp();
    ViewApp(const ViewApp&) = delete;
    ViewApp& operator=(const ViewApp&) = delete;

    /// Builds one frame between ImGui::NewFrame() and ImGui::Render(): input, model update,
    /// texture upload and panels, for a window of `window` pixels.
    void frame(glm::vec2 window);
    /// Draws the image and the overlay into the current framebuffer (before ImGui's draw data).
    void draw(glm::vec2 window, int framebuffer_width, int framebuffer_height) const;

    /// Opens the first .lua file of a drop on the window.
    void drop(const std::vector<std::string>& paths);
    /// Whether the person asked to quit (Ctrl+Q).
    bool quit_requested() const { return quit_; }
    /// Whether nothing is being rendered or loaded (the platform may then wait for events).
    bool idle() const;

    /// The panels' state (to start with the overlay header open, for instance).
    PanelState& panels() { return state_; }
    /// Where the image was put in the last frame.
    const ImageLayout& layout() const { return layout_; }
    /// The texture side (upload counts).
    const ImageView& image_view() const { return *image_; }
    /// The inspection tools' state: zoom, sidebar, A/B reference and mode, statistics, readout.
    InspectState& inspect() { return inspect_; }
    const InspectState& inspect() const { return inspect_; }
    /// Tests and screenshots: the hover readout at this window point whatever the mouse does
    /// (nullopt: the mouse decides again).
    void force_hover(std::optional<glm::vec2> point) { forced_hover_ = point; }
    /// The image area's size (the window without the sidebar when it is shown).
    glm::vec2 image_area() const { return area_; }

private:
    void handle_mouse(glm::vec2 window);
    void handle_keys();
    void note_camera_change();
    void update_overlay_triangles();
    void update_inspection();
    void load_reference();
    void handle_region_keys();
    void draw_region_outline() const;

    ViewModel& model_;
    PanelState state_;
    std::unique_ptr<ImageView> image_;
    std::unique_ptr<OverlayRenderer> overlay_;
    ImageLayout layout_;
    bool dragging_[3] = {false, false, false};
    std::uint64_t overlay_version_ = ~std::uint64_t(0);
    float overlay_scale_ = 0.0f;
    bool quit_ = false;
    InspectState inspect_;
    std::optional<glm::vec2> forced_hover_;
    glm::vec2 area_{0.0f};
    bool panning_image_ = false, dragging_split_ = false, mouse_moved_ = false;
    std::uint64_t uploaded_reference_ = 0;
    float stats_exposure_ = 0.0f;
    RegionDrag region_drag_;  // the render region being drawn (Shift+drag, or Ctrl+B then drag)
    HoverRest hover_rest_;
    glm::dvec3 shown_eye_{0.0}, shown_target_{0.0};
};

}  // namespace caustica::ui
