// The preview's state and actions, free of GL so that they can be tested: the open scene, the
// orbit camera, the caustic knobs, render and display settings, the overlay and saving. Every
// change becomes a modified RenderJob for the one RenderSession, whose stage cache decides what
// is redone (camera: image only; N or max distance: gather only; photons: no BVH rebuild). The
// progressive integrator refines without limit unless a stopping rule is given (command line,
// gr.option or the panel); its rules and a pause change nothing else.
//
// What you see is what you save (docs/PREVIEW.md): a job starts as `caustica render SCENE [options]`
// composes it (the script's gr.option, then the command-line options given for that scene), and
// every choice of the person is an override on top, listed by differences(), undoable, and
// written back as the options of command_line().
#pragma once

#include "core/scene/orbit_camera.h"
#include "ui/camera_bookmarks.h"
#include "ui/caustic_knobs.h"
#include "ui/integrator_memory.h"
#include "ui/overlay_geometry.h"
#include "ui/preview_driver.h"
#include "ui/save_image.h"
#include "ui/saved_accumulation.h"
#include "ui/scene_source.h"
#include "ui/view_transform.h"

#include <future>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace caustica::ui {

/// How the model is set up.
struct ModelConfig {
    /// Command-line options of `caustica view`: they win over gr.option, as in `render`, and belong
    /// to `option_scene` only (to the first scene opened when that is ""); scenes opened later start
    /// from their own gr.option calls, as `caustica render OTHER.lua` would.
    std::vector<std::string> option_tokens;
    std::string option_scene;
    std::string recent_file;                 ///< where the recent list is kept ("" = nowhere)
    DriverSettings driver;
    double script_timeout = 60.0;            ///< seconds a scene script may run
    std::size_t script_memory_bytes = std::size_t(2) << 30;  ///< the script's memory budget (0 = none)
    std::vector<std::string> allow_read;     ///< folders besides the scene's that scripts may read
};

/// Display-only settings: applied in the shader, never re-rendered.
struct DisplaySettings {
    float exposure = 0.0f;  ///< stops added to the job's --exposure: the image is multiplied by 2^(sum)
    bool srgb = false;      ///< sRGB transfer curve (else clamped linear, as the batch PNG)
    /// Saving a PNG applies this exposure on top of the job's --exposure (off: the PNG is what
    /// `caustica render` writes, whatever the display shows).
    bool exposure_to_png = false;
    /// The tone curve the person picked (nullopt: the job's --tonemap). A saved PNG uses it, and
    /// the command line gives it as --tonemap when it differs from the job's.
    std::optional<Tonemap> tonemap;
};

/// What the projection-map overlay shows.
struct OverlaySettings {
    bool enabled = false;
    bool cells = false;  ///< also the occupied cells
    int light = 0;       ///< index into the maps of the last photon pass

    bool operator==(const OverlaySettings&) const = default;
};

/// One way the preview differs from what `caustica render SCENE [its options]` would render.
struct Difference {
    std::string id;       ///< what reset_difference() takes: "preset", "knob:photons", "stop", "threads", ...
    std::string label;    ///< "photons"
    std::string scene;    ///< the value render would use
    std::string shown;    ///< the preview's
    std::string note;     ///< e.g. "no command-line option: use Copy camera" ("" = none)
};

/// The person's choices that undo and redo step through (not the camera).
struct Choices {
    CausticKnobs person_knobs;
    KnobOverrides overrides;
    std::string preset;                    ///< "" = none, else draft, preview or final (--quality)
    std::optional<StopRules> stop_rules;   ///< the person's stopping rules

    bool operator==(const Choices&) const = default;
};

/// The quality presets the picker offers (--quality), "" first for none.
inline constexpr const char* quality_preset_names[] = {"", "draft", "preview", "final"};

/// The largest caustic photon count per light whose photon map fits the memory the photon pass
/// allows (60% of the machine's memory, core/photons/photon_tracer.cpp): the photon slider's end.
long long photon_memory_limit();

/// A gr.render camera as Lua to paste into a script: "{ex, ey, ez}, {vx, vy, vz}, {ux, uy, uz}, fov".
std::string camera_lua(const CameraDesc& camera);

/// A hint to tick --a4 for a script whose first render puts more of its objects (their origins) in
/// the camera's view under the course conventions (pre-multiplied transforms, unit cube) than under
/// the original's it is rendered with; "" when the conventions agree or the original's keep as much
/// in view.
std::string course_scene_hint(const SceneScript& script);
/// The other way round, for a scene given --a4: a hint to untick it when the original's conventions
/// put more objects in view ("" otherwise).
std::string seed_scene_hint(const SceneScript& script);

/// A path quoted for a POSIX shell when it needs to be.
std::string shell_quote(const std::string& word);

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
    /// Warnings of the script and of the render ("file:line: message"), as printable_text shows them.
    std::vector<std::string> warnings() const;
    /// The last scene or render error ("file:line: message") as printable_text shows it, "" when none.
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

    // --- what differs from `caustica render` (docs/PREVIEW.md, "What you see is what you save")
    /// The quality preset the person picked ("" = none: the scene's own values).
    const std::string& preset() const { return inputs_.preset; }
    /// Picks a preset (applied after the scene's options, before the person's knobs, like
    /// `render SCENE --quality P --knob ...`). Throws InputError for an unknown name.
    void set_preset(const std::string& name);
    /// The options of the scene as `caustica render SCENE [its command-line options]` uses them.
    Options scene_options() const;
    /// Everything shown that differs from that render, in panel order.
    std::vector<Difference> differences() const;
    /// Takes back one difference (by Difference::id); "all" takes back every one but the camera.
    void reset_difference(const std::string& id);
    /// The command-line options of the scene shown (those given to `view` for it, and --a4 as
    /// ticked), which every render of it starts from.
    const std::vector<std::string>& scene_tokens() const { return inputs_.tokens; }
    /// The options the person's choices add after scene_tokens().
    std::vector<std::string> person_tokens() const;
    /// `caustica render SCENE.lua --opt ... -o FILE` that renders what is shown, bit for bit (the
    /// preview seeds as --reproducible does), except what command_line_notes() say.
    std::string command_line() const;
    /// The file command_line() writes (-o): the name Save proposes, or, when the preview last saved
    /// its image there, that name with "-render" before the extension, so the command never
    /// overwrites the saved image.
    std::string command_output() const;
    /// What the command line cannot reproduce (orbited camera, resolution scale, ...).
    std::vector<std::string> command_line_notes() const;
    /// Whether --a4 is in effect for the scene shown, and where it comes from ("" = off).
    std::string a4_origin() const;
    /// Ticks or unticks --a4 for the scene shown (a per-scene command-line option; not possible when
    /// the script's gr.option sets it). Scenes opened later keep their own setting.
    void set_a4(bool on);
    /// A hint when the scene looks like a course (CS488 A4) scene rendered without --a4, or like a
    /// scene in the original's conventions rendered with it ("" = none).
    const std::string& a4_hint() const { return a4_hint_; }

    // --- undo and redo of the person's choices (knobs, preset, integrator, stopping rules)
    void undo();
    void redo();
    bool can_undo() const { return !undo_.empty(); }
    bool can_redo() const { return !redo_.empty(); }
    /// While on, consecutive changes make one undo step (a slider being dragged).
    void set_coalescing(bool on);

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

    // --- render region (docs/PREVIEW.md, "Render region")
    /// Renders only these pixels of the shown image (clamped to it; empty: the whole image): every
    /// pass goes there and the other pixels keep the last image. Never restarts an accumulation:
    /// it goes on in the region, its pixels keeping their passes. Not a choice to undo, and not an
    /// option of the copied command line: a working tool, like the pause.
    void set_render_region(const RenderRegion& region);
    /// Back to the whole image (the accumulation goes on over every pixel).
    void clear_render_region() { set_render_region({}); }
    /// The region in effect (empty: none). Moving the camera, resizing the image or opening
    /// another scene clears it: it marks pixels of the view it was drawn on.
    const RenderRegion& render_region() const { return driver_.region(); }

    // --- render and display settings
    /// Render resolution relative to the script's (0.1 .. 2).
    double resolution_scale() const { return inputs_.resolution_scale; }
    /// Sets it (clamped); only the image is rendered again.
    void set_resolution_scale(double scale);
    /// Render threads in effect (0 = all cores): the script's or command line's until set here.
    int threads() const;
    /// Sets the render threads (0 = all cores); only the image is rendered again.
    void set_threads(int threads);
    /// Exposure, tone curve and sRGB display (change them freely: display only).
    DisplaySettings& display() { return display_; }
    const DisplaySettings& display() const { return display_; }
    /// What the viewport shows: the job's --exposure plus the display's, the display's curve (or
    /// the job's --tonemap), the sRGB choice; a PNG saved with "apply the display exposure" is
    /// written with exactly this (docs/PREVIEW.md, "View transform").
    ViewTransform view_transform() const;

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
    /// "requested N photons, none shot: REASON" when the render asked for caustic photons and its
    /// statistics show none stored ("" otherwise, and before the render has got that far).
    std::string photons_note() const;
    /// The job that is rendered next or now (camera, options, size).
    RenderJob current_job() const;
    /// Whether a change has not reached the renderer yet (an edit, a load, a --orbit to apply).
    bool changes_pending() const { return dirty_ || pending_orbit_.has_value() || loading() || driver_.pending(); }

    // --- saving
    /// The file Save proposes: the script's output name.
    std::string default_save_path() const;
    /// Saves the shown image as PNG, EXR or PFM by the extension (see save_preview_image).
    SaveResult save(const std::string& path, bool overwrite);
    /// Whether the render is still in progress (saving now gives a partial image).
    bool rendering() const;
    /// Whether the render in progress ends by itself (not a progressive refinement without a rule).
    bool render_ends() const;
    /// "3 of 10 passes", "2 passes", "pass 1 of 2": what a save now would hold.
    std::string passes_text() const;
    /// Saves once the render in progress has finished (at once when it has).
    void save_when_done(const std::string& path, bool overwrite);
    /// The path a save waits for ("" = none); cancel_scheduled_save() drops it.
    const std::string& scheduled_save() const { return scheduled_save_; }
    void cancel_scheduled_save() { scheduled_save_.clear(); }
    /// The outcome of a scheduled save, once.
    std::optional<SaveResult> take_scheduled_result();
    /// The absolute path of the last image written ("" = none yet).
    const std::string& last_saved() const { return last_saved_; }

    // --- resuming a saved accumulation (docs/PREVIEW.md, "Resume")
    /// What the model has to tell the person about saved accumulations, once: one continued, one
    /// ignored and why, the state a save while refining wrote at the end of its pass.
    std::optional<ModelNote> take_note() { return std::exchange(note_, std::nullopt); }

    // --- camera as text
    /// The camera shown as gr.render arguments (see camera_lua).
    std::string camera_text() const { return camera_lua(orbit_.desc()); }
    /// Moves the camera to `camera` (a bookmark): its eye, view and up; the script's angle stays.
    void go_to_camera(const CameraDesc& camera);
    /// Named cameras per scene, kept beside the recent list (ModelConfig::recent_file).
    CameraBookmarks& bookmarks() { return bookmarks_; }
    const CameraBookmarks& bookmarks() const { return bookmarks_; }

    // --- the integrator picked per scene (docs/PREVIEW.md, "What you see is what you save")
    /// Whether the integrator shown is the person's pick for this scene, kept for the next time it
    /// is opened (here or in a later run); like any pick it is listed as a difference and carried
    /// by the command line.
    bool integrator_kept() const;

    /// Test hook: how often the session rebuilt the scene, shot photons and rendered.
    RenderSession::StageCounters stage_counters() const { return driver_.session().stage_counters(); }

private:
    /// Everything a job is made from except the camera.
    struct JobInputs {
        std::shared_ptr<const SceneScript> scene;
        std::string scene_path;
        int render_index = 0;
        std::vector<std::string> tokens;  ///< the scene's command-line options (view's, --a4 ticked)
        std::string preset;               ///< the person's --quality ("" = none)
        CausticKnobs person_knobs;
        KnobOverrides overrides;
        int threads = -1;  ///< < 0: as the script and command line say
        double resolution_scale = 1.0;
    };

    RenderJob compose(const JobInputs& inputs) const;
    CausticKnobs script_knobs(const JobInputs& inputs) const;  // the scene's, with the person's preset
    Options base_options(const JobInputs& inputs, bool with_preset) const;
    CausticKnobs effective_knobs(const JobInputs& inputs) const;
    StopRules stop_rules_for(const RenderJob& script_job, const Options& options) const;  // options: with the command line's
    bool same_inputs(const JobInputs& a, const JobInputs& b) const;
    void install(LoadedScene loaded);
    void watch_current();
    void resolve_target();
    void update_overlay();
    void mark_dirty() { dirty_ = true; }
    Choices choices() const;
    void restore(const Choices& choices);
    void record_undo();
    void forget_choices();  // another scene: start clean
    void update_a4_hint();
    void clear_region_of_another_view(const RenderJob& next);  // the camera or size changed
    std::vector<std::string>& tokens_of(const std::string& path);
    void recall_integrator();       // a scene opened: the person's integrator for it, unless its command line sets one
    void remember_integrator();     // after a change: keeps the person's integrator for the scene (or forgets it)
    // Saved accumulations (ui/view_model_resume.cpp).
    void request_job(const RenderJob& job);  // continuing the accumulation saved beside Save's name, if any
    RenderJob rendered_job(const RenderJob& shown, const JobInputs& inputs) const;  // as `caustica render` composes it
    std::string save_accumulation(const std::string& image_path, bool inside_current_folder);  // beside a saved image
    void follow_saved_accumulations();  // per frame: what the driver did with one, a snapshot to write

    ModelConfig config_;
    SceneSource source_;
    PreviewDriver driver_;
    std::shared_ptr<const SceneScript> scene_;
    std::string scene_path_, watched_path_;
    JobInputs inputs_;
    std::optional<JobInputs> running_inputs_, committed_inputs_, requested_inputs_;
    std::uint64_t seen_restarts_ = 0;
    std::optional<StopRules> person_stop_rules_;
    std::vector<std::pair<std::string, std::vector<std::string>>> scene_tokens_;  // absolute path -> tokens
    bool tokens_assigned_ = false;  // option_tokens went to their scene
    std::vector<Choices> undo_, redo_;
    bool coalescing_ = false, group_open_ = false;
    std::string a4_hint_;
    std::string scheduled_save_, last_saved_;
    bool scheduled_overwrite_ = false;
    std::optional<SaveResult> scheduled_result_;
    CameraBookmarks bookmarks_;
    IntegratorMemory integrators_;
    /// The scene and the integrator the memory holds for it as this model last read or wrote it.
    std::string remembered_scene_;
    std::optional<IntegratorKind> remembered_integrator_;
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

    SavedAccumulations saved_accumulations_;
    std::weak_ptr<const SceneScript> looked_for_state_of_;  // the scene a state was last looked for
    std::string continuing_from_;  // the state file handed to the driver
    /// A save while refining: its state is written from the snapshot of the pass under way.
    struct StateToWrite {
        std::string path, shown;  // as written, and absolute for the person
        bool inside_current_folder = false;
        RenderJob shown_job;  // the preview's job when asked: the state written must be its
        RenderJob rendered;
        std::uint64_t restarts = 0;  // the driver's, when asked: another job started since ends it
    };
    std::optional<StateToWrite> state_to_write_;
    // The job (key_without_scene) whose accumulation the last save wrote beside last_saved_, if
    // one was: while the job is that one, the command line's notes say how to continue it.
    std::optional<AccumulationKey> saved_state_key_;
    std::optional<ModelNote> note_;

    CameraDesc region_camera_;  // the view the render region was drawn on
    int region_width_ = 0, region_height_ = 0;
};

}  // namespace caustica::ui
