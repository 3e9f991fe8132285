// The inspection tools' state and panels (docs/INSPECTION.md): the "Inspect" sidebar section
// (histogram, clipped fraction, A/B comparison with its metrics and heat-map legend), the hover
// readout beside the cursor, and the button that hides the sidebar. ViewApp owns the state and
// does the GL side (the reference texture, the shader's comparison modes).
#pragma once

#include "core/render/render_session.h"
#include "ui/inspection.h"
#include "ui/view_model.h"

#include <array>
#include <optional>
#include <string>

namespace caustica::ui {

/// How the shown image is compared with the reference (shaders/image.frag's u_mode).
enum class CompareMode { off = 0, split = 1, difference = 2, heat = 3 };

/// "off", "split", "difference", "relative error".
const char* compare_mode_name(CompareMode mode);

/// Inspection state kept by ViewApp between frames.
struct InspectState {
    bool sidebar_hidden = false;
    ImageZoom zoom;

    // A/B comparison: the current image (A) against a reference (B).
    CompareMode mode = CompareMode::off;
    float split = 0.5f;          ///< split mode: fraction of the image width shown as A (left)
    float difference_stops = 0.0f;  ///< difference mode: |A - B| x 2^stops before the display exposure
    float epsilon = 1e-3f;       ///< relative error: |A - B|_1 / max(|B|_1, epsilon)
    Image reference;             ///< empty when none
    std::string reference_name;  ///< "snapshot" or the file read
    std::uint64_t reference_version = 0;  ///< increments when `reference` changes (texture upload)
    std::array<char, 1024> reference_path{};
    std::string reference_problem;  ///< why the reference cannot be compared (size, read error)

    // Statistics of the shown image, refreshed at most every `stats_interval` seconds.
    LuminanceHistogram histogram;
    std::optional<ImageComparison> metrics;
    double stats_at = -1e9;
    bool stats_due = true;
    float stats_ms = 0.0f;  ///< time of the last refresh

    // Hover readout.
    bool readout = true;                  ///< show it beside the cursor
    std::optional<glm::vec2> hover;       ///< window point under the cursor (or forced by a test)
    PixelReadout pixel;
    std::optional<SurfaceInspection> surface;  ///< RenderSession::inspect at the pixel's centre
    glm::ivec2 inspected{-1, -1};          ///< the pixel `surface` belongs to
    std::uint64_t inspected_generation = ~std::uint64_t(0);
    std::uint64_t inspected_maps = ~std::uint64_t(0);
    glm::vec2 readout_size{260.0f, 130.0f};  ///< the readout box's size in the last frame drawn

    // Requests from the panel, carried out by ViewApp in the same frame.
    bool snapshot_requested = false, load_requested = false, clear_requested = false;
    bool open_header = false;  ///< unfold the Inspect section once
};

/// Seconds between two refreshes of the histogram and the metrics.
inline constexpr double stats_interval = 0.25;

/// The Inspect section, appended to the sidebar window.
void draw_inspect_section(InspectState& state, const ViewModel& model);
/// The readout box beside the cursor (when the cursor rests on the image), clear of the cursor and
/// inside the image area (`area`: its size from the window's top-left; ui/hover_readout.h).
void draw_hover_readout(InspectState& state, const ImageLayout& layout, glm::vec2 area);
/// The button at the image area's top-right corner that hides or shows the sidebar.
void draw_sidebar_toggle(InspectState& state, float area_right);
/// The heat map's scale as a strip of colour with its labels.
void draw_heat_legend(float width);

}  // namespace caustica::ui
