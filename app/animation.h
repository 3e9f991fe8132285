// Animations for `caustica render` (docs/ANIMATION.md): `--frames A:B` picks frames,
// `--orbit-frames N` turns the script's camera 360 degrees around a target in N frames. This file
// plans the frames (which jobs, which cameras, which files) without rendering anything, so that one
// process can render them all or several processes can share them out.
#pragma once

#include "core/scene/scene_desc.h"

#include <functional>
#include <string>
#include <vector>

namespace caustica {

/// The most frames --orbit-frames and --frames accept.
inline constexpr int max_animation_frames = 100000;

/// What the command line asks of an animation.
struct AnimationRequest {
    int first = 0, last = 0;  ///< --frames A:B (numbered from 1, inclusive); 0 when not given
    int orbit_frames = 0;     ///< --orbit-frames N; 0 when not given
    std::string frames_text;  ///< "--frames A:B" as given, for messages

    bool frames_given() const { return first > 0; }
    bool orbit() const { return orbit_frames > 0; }
    /// Whether anything was asked (the frames are then numbered in the images' metadata).
    bool any() const { return frames_given() || orbit(); }
};

/// Removes --frames A:B (--frames=A:B, --frames N for frame N alone) and --orbit-frames N
/// (--orbit-frames=N) from `tokens` and returns what they ask. Throws InputError on a value that
/// is not a frame number or range (0, negative, A after B, more than max_animation_frames).
AnimationRequest take_animation_arguments(std::vector<std::string>& tokens);

/// One image of an animation.
struct AnimationFrame {
    RenderJob job;     ///< what to render (the camera already orbited)
    std::string path;  ///< the file to write
    int number = 0;    ///< the frame's number, from 1: its gr.render's, or its place in the orbit
    int count = 0;     ///< the frames of the whole animation (before --frames picks some)
    int job_index = 0; ///< the gr.render (index into the script's jobs) the frame renders
    /// `path` comes from the script's gr.render name (no -o): it is written only inside the
    /// current folder (docs/RELIABILITY.md, section 1).
    bool named_by_script = false;
};

/// The frames to render, in order, with what to tell the user.
struct AnimationPlan {
    std::vector<AnimationFrame> frames;
    std::vector<std::string> warnings;
    /// --orbit-frames: the frames' cameras still need the target (aim_orbit); the frames hold
    /// the script's camera until then.
    bool needs_target = false;
};

/// Plans the frames of `jobs` (the script's gr.render calls, command-line options applied);
/// `output` is -o or "". Without --orbit-frames the frames are the jobs (1..count), written where
/// they are today: the script's names (then named_by_script), -o OUT when there is one job, else
/// OUT-k for the k-th.
/// With --orbit-frames N they are N views of the first job, OUT-0001... (or the script's name
/// with -0001 before the extension). --frames keeps a sub-range. Throws InputError when
/// --frames lies outside the frames there are (naming the range).
AnimationPlan plan_animation(const AnimationRequest& request, const std::vector<RenderJob>& jobs, const std::string& output);

/// Turns the cameras of an orbit plan around the target `target_distance` along the script's view
/// (<= 0 or not finite: the ray hits nothing, default_target_distance is used). Does nothing to
/// a plan without --orbit-frames.
void aim_orbit(AnimationPlan& plan, double target_distance);

/// The distance from a job's eye to the first surface its central view ray hits; <= 0 for none.
using TargetDistance = std::function<double(const RenderJob&)>;

/// plan_animation then aim_orbit with `target` (called once, for the orbited job, and only for
/// --orbit-frames).
AnimationPlan plan_frames(const AnimationRequest& request, const std::vector<RenderJob>& jobs, const std::string& output,
                          const TargetDistance& target);

/// Frame `frame` (1..count) of an orbit of `count` frames: `script` turned by 360 * (frame - 1)
/// / count degrees about its up vector around the target `target_distance` along its view.
/// Frame 1 is `script` bit for bit.
CameraDesc orbit_frame_camera(const CameraDesc& script, double target_distance, int frame, int count);

/// `base` with "-0001" (frame 1; zero-padded to max(4, digits of count)) before its extension.
std::string numbered_frame_path(const std::string& base, int frame, int count);

/// "3/300": the metadata text of frame 3 of 300.
std::string frame_label(const AnimationFrame& frame);

}  // namespace caustica
