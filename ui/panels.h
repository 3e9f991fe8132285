// The preview's ImGui panels: the sidebar sections (scene, caustics, view, statistics) and what
// floats over the image (status line, error banner, help, overwrite question). They read and
// change the ViewModel only; nothing here touches GL.
#pragma once

#include "ui/image_layout.h"
#include "ui/knob_drag.h"
#include "ui/view_model.h"

#include <array>
#include <map>
#include <string>
#include <vector>

namespace caustica::ui {

/// Width of the sidebar in pixels (the image gets the rest of the window).
inline constexpr float sidebar_width = 370.0f;

/// State of the panels between frames (text fields, open dialogs, messages).
struct PanelState {
    std::array<char, 1024> open_path{};   ///< the Open panel's path field
    std::array<char, 1024> save_path{};   ///< the Save field
    std::string save_path_scene;          ///< the scene the save path was proposed for
    bool show_help = false;
    bool ask_overwrite = false;           ///< open the overwrite question next frame
    std::string message;                  ///< a passing message ("wrote x.png")
    double message_until = 0.0;           ///< ImGui time at which the message goes
    bool open_overlay_header = false;     ///< unfold the overlay settings once (--overlay)
    std::vector<std::string> scene_files; ///< listing of the Open panel
    double scene_files_at = -1e9;         ///< when it was listed
    float ui_frame_ms = 0.0f;             ///< the last UI frame's CPU time, for the statistics

    /// A field where a knob's value is typed (checked on Enter, never clamped).
    struct TypedField {
        std::array<char, 64> text{};
        bool editing = false;   ///< the text is the person's, not the knob's value
        std::string error;      ///< why the typed value was not applied
        std::string error_value;  ///< the knob's value then: the error goes when the knob changes
    };
    std::map<std::string, TypedField> typed;
    std::string type_into;                ///< the knob whose typed field takes the keyboard next (Ctrl+click)

    // Logarithmic knobs (ui/knob_drag.h)
    LogKnobDrag knob_drag;                ///< the drag in progress
    std::string knob_dragged;             ///< the knob it drags ("neighbours N"); empty: none
    /// Where a widget was drawn in the last frame (window pixels).
    struct WidgetRect {
        glm::vec2 min{0.0f}, max{0.0f};
    };
    std::map<std::string, WidgetRect> knob_rects;  ///< the drag field of each knob drawn in the last frame (tests)
    std::string rules_error;              ///< why a typed stopping rule was not applied

    // Saving
    bool ask_save_choice = false;         ///< open the "save now / when done" question next frame
    bool overwrite_when_done = false;     ///< the overwrite question is for a save when done
    bool message_sticky = false;          ///< the message stays until dismissed
    int question_frame = -1;              ///< ImGui frame in which the last question opened
    float image_area_width = 0.0f;        ///< width of the image area; 0 = the window's minus the sidebar
    float sidebar_content_end = 0.0f;     ///< where the sidebar's content ended in the last frame (ImGui's content y)
    // Where the last frame put the status line and the error banner (window pixels: min x, min y,
    // max x, max y; zero when not shown): the banner goes under the status line.
    glm::vec4 status_box{0.0f}, error_box{0.0f};

    // Camera
    std::array<char, 64> bookmark_name{};
    std::string camera_text;              ///< the last copied camera, shown under the button
    std::string camera_text_scene;        ///< the scene it was copied in (another scene forgets it)

    /// Whether the last sidebar showed the scene's values (knobs, view, statistics): not before a
    /// scene has loaded, so that no frame shows the panels' defaults in their place.
    bool scene_values_shown = false;
};

/// The panels' look: ImGui's dark colours, a little tighter so that every section fits 720 pixels.
void apply_panel_style();

/// The sidebar with every section.
void draw_sidebar(ViewModel& model, PanelState& state, glm::vec2 window);

/// Scene section: path field, scene files, recent scenes, render choice, warnings.
void draw_scene_section(ViewModel& model, PanelState& state);
/// Caustics section: the knobs, views and the projection-map overlay settings.
void draw_caustics_section(ViewModel& model, PanelState& state);
/// Text lines of the differences region: its height, whatever the rows.
inline constexpr float differences_region_lines = 7.0f;
/// What differs from `caustica render SCENE`, in a region of fixed height that scrolls: a reset
/// per row, reset all, the command line.
void draw_differences_section(ViewModel& model);
/// View section: camera, display, resolution and threads, saving.
void draw_view_section(ViewModel& model, PanelState& state);
/// Statistics section: photons, stage times, passes, samples, rays/s, time per pass.
void draw_stats_section(const ViewModel& model, const PanelState& state);

/// Progressive refinement: Pause/Resume and the stopping rules (pass limit, time, target error).
void draw_refinement_controls(ViewModel& model, PanelState& state);
/// "37 of 100 passes  |  370M photons  |  37 spp  |  est. error 4.2% (...)  |  radius 0.031".
std::string refinement_summary(const SessionProgress& accumulation);
/// The parts of refinement_summary, the status line's pieces that never break across lines.
std::vector<std::string> refinement_parts(const SessionProgress& accumulation);
/// What the render does, in words: "refining", "paused", "shooting photons", "stopped by the pass limit".
std::string render_state(const ViewModel& model);
/// A count in few digits: 950, 12.5k, 370M, 1.2G.
std::string short_count(double n);
/// A progress bar of the photon stage while photons are shot (nothing otherwise).
void photon_progress_bar(const SessionProgress& progress, float width);

/// Status line, error banner, help, overwrite question and messages over the image area.
void draw_image_overlays(ViewModel& model, PanelState& state, const ImageLayout& layout, glm::vec2 window);

/// Saves to the Save field's path (Save button and Ctrl+S): while rendering it asks whether to save
/// now (the passes so far) or when done; asks before replacing a file.
void request_save(ViewModel& model, PanelState& state);

/// Saves the shown samples now (asking before replacing a file).
void save_now(ViewModel& model, PanelState& state);
/// Saves once the render has finished (asking now before replacing a file).
void save_when_done(ViewModel& model, PanelState& state);
/// A save's message with the full path written.
std::string saved_message(const ViewModel& model, const SaveResult& result);

/// Shows a passing message for a few seconds (`sticky`: until dismissed).
void show_message(PanelState& state, const std::string& text, bool sticky = false);

}  // namespace caustica::ui
