// The frame loop's timing (window and headless alike), which decides how soon a camera move
// shows. A fixed 60 Hz beat would show the coarse preview of a new view up to a whole frame
// period after the renderer finished it, and meanwhile draw frames of the previous image or of
// half-done blocks, whose 10-20 ms of software GL are taken from the two cores the renderer needs
// (docs/PERFORMANCE.md, the preview). Here: the wait between frames ends when a new view's coarse
// preview is complete (wait_for_next_frame), and a frame with nothing new to show while that
// preview renders is not drawn (FrameSkipper). Header only: both platforms' executables and the
// preview benchmark use it, and caustica-view links no headless code.
#pragma once

#include "ui/view_model.h"

#include <algorithm>
#include <chrono>
#include <thread>
#include <type_traits>

namespace caustica::ui {

/// How the loop paces its frames.
struct FramePacing {
    std::chrono::microseconds period{16667};  ///< 60 frames a second at most: the renderer needs the cores
    /// A frame due while the coarse preview of a new view is being rendered waits for it up to
    /// this long past its time (it could only show some of the new view's blocks).
    std::chrono::microseconds preview_grace{25000};
    /// ... but only while the render is this young: a render still preparing (a photon pass after
    /// a knob change) lets frames run at their pace.
    double preview_young_seconds = 0.15;
    /// A frame with nothing new in the image may leave the screen as it is while a coarse preview
    /// is being rendered, as long as the screen was drawn less than this long ago.
    std::chrono::microseconds max_undrawn{60000};
};

/// Where the newest render's coarse preview (its first image pass) stands, from the session's
/// live progress: being rendered (or due to start), complete but not shown yet, or neither.
enum class CoarsePreview { none, rendering, unshown };

inline CoarsePreview coarse_preview(const PreviewDriver& driver, const FramePacing& pacing = {}) {
    auto first_pass_done = [](const SessionProgress& p) {
        const std::size_t per_pass = p.passes > 0 ? p.tiles_total / static_cast<std::size_t>(p.passes) : 0;
        return per_pass > 0 && p.tiles_done >= per_pass;
    };
    if (driver.pending()) return CoarsePreview::rendering;  // a restart is due: its preview follows
    if (!driver.busy()) return CoarsePreview::none;
    const SessionProgress& shown = driver.progress();  // as the last frame fetched it
    if (shown.generation == driver.generation() && first_pass_done(shown)) return CoarsePreview::none;
    const SessionProgress live = driver.session().progress();
    if (live.generation != driver.generation()) return CoarsePreview::none;
    if (first_pass_done(live)) return CoarsePreview::unshown;
    return live.running && live.elapsed_seconds < pacing.preview_young_seconds ? CoarsePreview::rendering
                                                                              : CoarsePreview::none;
}

/// Decides which frames are drawn. A frame just built (ViewApp::frame, ImGui::Render) may skip
/// drawing and presenting, leaving the last frame on screen, when it brings no tile of a render
/// not shown yet (at most the last tiles of one already on screen, whose view the camera has just
/// left), the coarse preview of a new view is being rendered (the frame showing it follows as soon
/// as it is complete, wait_for_next_frame), and the screen was drawn less than
/// `pacing.max_undrawn` ago, so the panels never lag by more. Drawing the window with software GL
/// takes 10-20 ms of the two cores that preview needs: skipping the frame that reads a drag shows
/// the new view sooner. In a continuous drag every frame shows the previous move's preview, a
/// render not shown yet, and is drawn.
class FrameSkipper {
public:
    using clock = std::chrono::steady_clock;

    /// Whether the frame just built may leave the screen as it is. Call once a frame, after
    /// ViewApp::frame (which fetched the driver's tiles).
    bool may_skip(const PreviewDriver& driver, const FramePacing& pacing = {}) {
        for (std::uint64_t g : driver.changed_generations()) uploaded_ = std::max(uploaded_, g);
        const bool new_view = uploaded_ > shown_ || driver.size_changed();
        return !new_view && clock::now() - last_drawn_ < pacing.max_undrawn &&
               coarse_preview(driver, pacing) == CoarsePreview::rendering;
    }
    /// The frame was drawn and presented: what it uploaded is on screen.
    void drawn() {
        shown_ = std::max(shown_, uploaded_);
        last_drawn_ = clock::now();
    }

private:
    std::uint64_t uploaded_ = 0;  // the newest render whose tiles went to the texture
    std::uint64_t shown_ = 0;     // the newest render whose tiles were on screen
    clock::time_point last_drawn_{};
};

/// Waits for the next frame of a loop whose last frame began at `frame_start`, meanwhile letting
/// the model restart the renderer the moment it can (ViewModel::poll). Returns as soon as the
/// coarse preview of a new view is complete, so that it shows at once; a frame falling due while
/// that preview is still being rendered waits for it, up to `pacing.preview_grace`. Returns the
/// time the next frame starts. `each_poll` runs after every poll (the window's event polling, the
/// benchmark's probes); when it returns true, the wait ends at once (new input to answer).
template <typename EachPoll>
std::chrono::steady_clock::time_point wait_for_next_frame(ViewModel& model, std::chrono::steady_clock::time_point frame_start,
                                                          const FramePacing& pacing, EachPoll each_poll) {
    using clock = std::chrono::steady_clock;
    const clock::time_point due = frame_start + pacing.period, latest = due + pacing.preview_grace;
    for (;;) {
        model.poll();
        if constexpr (std::is_same_v<std::invoke_result_t<EachPoll>, bool>) {
            if (each_poll()) return clock::now();
        } else {
            each_poll();
        }
        const clock::time_point now = clock::now();
        const CoarsePreview preview = coarse_preview(model.driver(), pacing);
        if (preview == CoarsePreview::unshown || now >= latest) return now;
        if (now >= due && preview == CoarsePreview::none) return now;
        const clock::time_point until = now < due ? due : latest;
        std::this_thread::sleep_for(std::min<clock::duration>(until - now, std::chrono::microseconds(500)));
    }
}

inline std::chrono::steady_clock::time_point wait_for_next_frame(ViewModel& model, std::chrono::steady_clock::time_point frame_start,
                                                                 const FramePacing& pacing = {}) {
    return wait_for_next_frame(model, frame_start, pacing, [] {});
}

}  // namespace caustica::ui
