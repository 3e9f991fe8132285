// The preview's state and actions, free of GL so that they can be tested: the open scene, the
// orbit camera, the caustic knobs, render and display settings, the overlay and saving. Every
// change becomes a modified RenderJob for the one RenderSession, whose stage cache decides what
// is redone (camera: image only; N or max distance: gather only; photons: no BVH rebuild). The
// progressive integrator refines without limit unless a stopping rule is given (command line,
// gr.option or the panel); its rules and a pause change nothing else.
#pragma once

#include "ui/caustic_knobs.h"
#include "ui/orbit_camera.h"
#include "ui/overlay_geometry.h"
#include "ui/preview_driver.h"
#include "ui/save_image.h"
#include "ui/scene_source.h"

#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace caustica::ui {

/// How the model is set up.
struct ModelConfig {
    /// What the preview starts from before the scene's gr.option and the command line: the
    /// `preview` quality preset, chosen at the knee of the error/time curves (docs/ACCURACY.md).
    std::vector<std::string> default_tokens = {"--quality", "preview"};
    std::vector<std::string> option_tokens;  ///< command-line options; they win over gr.option, as in `render`
    std::string recent_file;                 ///< where the recent list is kept ("" = nowhere)
    DriverSettings driver;
    double script_timeout = 60.0;            ///< seconds a scene script may run
    std::size_t script_memory_bytes = std::size_t(2) << 30;  ///< the script's memory budget (0 = none)
    std::vector<std::string> allow_read;     ///< folders besides the scene's that scripts may read
};

/// Display-only settings: applied in the shader, never re-rendered.
struct DisplaySettings {
    float exposure = 0.0f;  ///< stops: the image is multiplied by 2^exposure
    bool srgb = false;      ///< sRGB transfer curve (else clamped linear, as the batch PNG)
};

/// What the projection-map overlay shows.
struct OverlaySettings {
    bool enabled = false;
    bool cells = false;  ///< also the occupied cells
    int light = 0;       ///< index into the maps of the last photon pass

    bool operator==(const OverlaySettings&) const = default;
};

/// The preview's model.
class ViewModel {
public:
    explicit ViewModel(ModelConfig config = {});
    ~ViewModel();
    ViewModel(const ViewModel&) = delete;
    ViewModel& operator=(const ViewModel&) = delete;

    // --- scenes
    /// Loads a scene script in the background; the current scene stays until it has loaded.
    void open(const std::string& path);
    /// Loads the current scene script again.
    void reload();
    /// The scene shown ("" before the first load).
    const std::string& scene_path() const { return scene_path_; }
    /// Whether a scene is shown.
    bool has_scene() const { return scene_ != nullptr; }
    /// Whether a script is being loaded.
    bool loading() const { return source_.loading(); }
    /// How many gr.render calls the script makes.
    int render_count() const { return scene_ ? static_cast<int>(scene_->renders.size()) : 0; }
    /// Which gr.render call is shown (0-based).
    int render_index() const { return inputs_.render_index; }
    /// Shows another gr.render of the script.
    void select_render(int index);
    /// Warnings of the script and of the render ("file:line: message").
    std::vector<std::string> warnings() const;
    /// The last scene or render error ("file:line: message"), "" when none.
    const std::string& error() const { return error_; }
    /// Hides the error.
    void clear_error() { error_.clear(); }
    /// The scene files, recent list and watcher.
    SceneSource& source() { return source_; }

    // --- camera
    /// Orbits the camera (degrees; see OrbitCamera::orbit).
    void orbit(double yaw_degrees, double pitch_degrees);
    /// Zooms by mouse-wheel steps (positive: closer).
    void zoom(double steps);
    /// Pans by a drag of (dx, dy) image pixels.
    void pan(glm::dvec2 image_pixels);
    /// Sets the orbit target at the surface under an image pixel; false when nothing is there.
    bool set_target_at(glm::vec2 image_pixel);
    /// Returns to the script's camera.
    void reset_camera();
    /// The orbit camera.
    const OrbitCamera& orbit_camera() const { return orbit_; }
    /// Orbits by these degrees (yaw, pitch) once the next scene's target is known (--orbit).
    void orbit_when_loaded(glm::dvec2 degrees) { pending_orbit_ = degrees; }

    // --- caustics
    /// The knobs in effect (the script's, with the person's changes).
    CausticKnobs knobs() const;
    /// Changes knobs; only what they invalidate is redone.
    void set_knobs(const CausticKnobs& knobs);
    /// Back to the script's knobs.
    void reset_knobs();

    // --- progressive refinement
    /// The stopping rules of the progressive integrator in effect: the person's, else those of the
    /// command line or gr.option, else none (refine until paused).
    StopRules stop_rules() const;
    /// Sets the person's stopping rules; the accumulation goes on under them (nothing restarts).
    void set_stop_rules(const StopRules& rules);
    /// Pauses (keeping the accumulation) or resumes the render; a change of the view or of a knob
    /// while paused is rendered, which ends the pause.
    void set_paused(bool paused);
    /// Whether the render is paused.
    bool paused() const { return driver_.paused(); }

    // --- render and display settings
    /// Render resolution relative to the script's (0.1 .. 2).
    double resolution_scale() const { return inputs_.resolution_scale; }
    /// Sets it (clamped); only the image is rendered again.
    void set_resolution_scale(double scale);
    /// Render threads in effect (0 = all cores): the script's or command line's until set here.
    int threads() const;
    /// Sets the render threads (0 = all cores); only the image is rendered again.
    void set_threads(int threads);
    /// Exposure and sRGB display (change them freely: display only).
    DisplaySettings& display() { return display_; }
    const DisplaySettings& display() const { return display_; }

    // --- overlay
    /// What the projection-map overlay shows.
    const OverlaySettings& overlay() const { return overlay_; }
    /// Changes it; never renders again (the overlay is drawn over the image).
    void set_overlay(const OverlaySettings& settings);
    /// The overlay in image pixels of the shown image (empty until traced).
    const OverlayImage& overlay_image() const { return overlay_image_; }
    /// Increments whenever overlay_image() changes.
    std::uint64_t overlay_version() const { return overlay_version_; }
    /// Whether the overlay shows the newest map (or there is none to show).
    bool overlay_settled() const;
    /// Why the overlay shows nothing, or what it shows ("" = nothing to say).
    std::string overlay_note() const;

    // --- the frame
    /// The per-frame step: scene loads, file changes, restarts, tiles, overlay. Never waits.
    void update();
    /// Between frames (while the platform waits for the next one): restarts the renderer as soon
    /// as it has stopped for a new job. Cheap; never waits.
    void poll() { driver_.poll(); }
    /// The render driver (image, tiles, progress, statistics).
    const PreviewDriver& driver() const { return driver_; }
    PreviewDriver& driver() { return driver_; }
    /// The job that is rendered next or now (camera, options, size).
    RenderJob current_job() const;
    /// Whether a change has not reached the renderer yet (an edit, a load, a --orbit to apply).
    bool changes_pending() const { return dirty_ || pending_orbit_.has_value() || loading() || driver_.pending(); }

    // --- saving
    /// The file Save proposes: the script's output name.
    std::string default_save_path() const;
    /// Saves the shown image (see save_preview_png).
    SaveResult save(const std::string& path, bool overwrite);

    /// Test hook: how often the session rebuilt the scene, shot photons and rendered.
    RenderSession::StageCounters stage_counters() const { return driver_.session().stage_counters(); }

private:
    /// Everything a job is made from except the camera.
    struct JobInputs {
        std::shared_ptr<const SceneScript> scene;
        std::string scene_path;
        int render_index = 0;
        CausticKnobs person_knobs;
        KnobOverrides overrides;
        int threads = -1;  ///< < 0: as the script and command line say
        double resolution_scale = 1.0;
    };

    RenderJob compose(const JobInputs& inputs) const;
    CausticKnobs script_knobs(const JobInputs& inputs) const;
    CausticKnobs effective_knobs(const JobInputs& inputs) const;
    StopRules stop_rules_for(const RenderJob& script_job, const Options& options) const;  // options: with the command line's
    bool same_inputs(const JobInputs& a, const JobInputs& b) const;
    void install(LoadedScene loaded);
    void watch_current();
    void resolve_target();
    void update_overlay();
    void mark_dirty() { dirty_ = true; }

    ModelConfig config_;
    SceneSource source_;
    PreviewDriver driver_;
    std::shared_ptr<const SceneScript> scene_;
    std::string scene_path_, watched_path_;
    JobInputs inputs_;
    std::optional<JobInputs> running_inputs_, committed_inputs_, requested_inputs_;
    std::uint64_t seen_restarts_ = 0;
    bool command_line_stop_rules_ = false;  // --passes, --time or --target-error among option_tokens
    std::optional<StopRules> person_stop_rules_;
    OrbitCamera orbit_;
    bool target_known_ = false;
    std::optional<glm::dvec2> pending_orbit_;
    bool dirty_ = false;
    std::string error_;
    DisplaySettings display_;

    OverlaySettings overlay_;
    std::future<OverlayWorld> overlay_trace_;
    std::optional<OverlayWorld> overlay_world_;
    std::uint64_t traced_maps_version_ = 0;
    OverlaySettings traced_settings_;
    bool overlay_stale_ = true;
    OverlayImage overlay_image_;
    std::uint64_t overlay_version_ = 0;
    CameraDesc projected_camera_;
    int projected_width_ = 0, projected_height_ = 0;
};

}  // namespace caustica::ui
