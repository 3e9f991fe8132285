#include "app/animation.h"

#include "core/scene/orbit_camera.h"
#include "core/scene/source_location.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>

namespace caustica {
namespace {

/// A frame number (or with `is_count` a number of frames): digits only, 1..max_animation_frames.
/// `shown` starts the messages ("--frames 2:x").
int parse_count(const std::string& shown, const std::string& text, const std::string& what, bool is_count = false) {
    const std::string below = is_count ? "expects " + what + " from 1 to " + std::to_string(max_animation_frames)
                                       : "frames are numbered from 1";
    if (text.empty()) throw InputError(shown.substr(0, shown.find(' ')) + ": expects " + what);
    const auto digits = [](const std::string& s) {
        return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
    };
    if (text[0] == '-' && digits(text.substr(1))) throw InputError(shown + ": " + below + (is_count ? "" : " (no negative numbers)"));
    long long value = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (ptr != end || !digits(text))
        throw InputError(shown + ": '" + text + "' is not a whole number (expects " + what + ")");
    if (ec == std::errc::result_out_of_range || value > max_animation_frames)
        throw InputError(shown + ": at most " + std::to_string(max_animation_frames) + " frames");
    if (value == 0) throw InputError(shown + ": " + below);
    return static_cast<int>(value);
}

void parse_frames(AnimationRequest& request, const std::string& value) {
    const std::string what = "A:B (frames A to B, numbered from 1) or N (frame N alone)";
    request.frames_text = "--frames " + value;
    const std::size_t colon = value.find(':');
    if (value.empty() || colon == 0 || (colon != std::string::npos && colon + 1 == value.size()))
        throw InputError(value.empty() ? "--frames: expects " + what : request.frames_text + ": expects " + what);
    if (colon == std::string::npos) {
        request.first = request.last = parse_count(request.frames_text, value, what);
        return;
    }
    const int first = parse_count(request.frames_text, value.substr(0, colon), what);
    const int last = parse_count(request.frames_text, value.substr(colon + 1), what);
    if (first > last)
        throw InputError(request.frames_text + ": the first frame (" + std::to_string(first) + ") is after the last (" +
                         std::to_string(last) + ")");
    request.first = first;
    request.last = last;
}

/// The file of the `index`-th of `count` gr.render calls: -o (numbered when there are several),
/// else the script's name.
std::string script_frame_path(const std::string& output, const RenderJob& job, std::size_t index, std::size_t count) {
    if (output.empty()) return job.output;
    if (count == 1) return output;
    std::filesystem::path p(output);
    return (p.parent_path() / (p.stem().string() + "-" + std::to_string(index + 1) + p.extension().string())).string();
}

std::string range_text(int count) { return "1:" + std::to_string(count); }

}  // namespace

AnimationRequest take_animation_arguments(std::vector<std::string>& tokens) {
    AnimationRequest request;
    std::vector<std::string> kept;
    for (std::size_t i = 0; i < tokens.size(); ++i) {
        const std::string& t = tokens[i];
        if (t == "--frames" || t == "--orbit-frames") {
            if (i + 1 >= tokens.size())
                throw InputError(t + (t == "--frames" ? ": expects A:B (frames A to B, numbered from 1) or N (frame N alone)"
                                                      : ": expects a number of frames"));
            const std::string& value = tokens[++i];
            if (t == "--frames")
                parse_frames(request, value);
            else
                request.orbit_frames = parse_count(t + " " + value, value, "a number of frames", true);
        } else if (t.rfind("--frames=", 0) == 0) {
            parse_frames(request, t.substr(9));
        } else if (t.rfind("--orbit-frames=", 0) == 0) {
            request.orbit_frames = parse_count("--orbit-frames " + t.substr(15), t.substr(15), "a number of frames", true);
        } else {
            kept.push_back(t);
        }
    }
    tokens = std::move(kept);
    return request;
}

CameraDesc orbit_frame_camera(const CameraDesc& script, double target_distance, int frame, int count) {
    OrbitCamera orbit(script, target_distance);
    if (frame > 1 && count > 0) orbit.orbit(360.0 * double(frame - 1) / double(count), 0.0);
    return orbit.desc();  // the script's own camera while unmoved (frame 1)
}

std::string numbered_frame_path(const std::string& base, int frame, int count) {
    const int width = std::max(4, static_cast<int>(std::to_string(count).size()));
    std::string number = std::to_string(frame);
    if (static_cast<int>(number.size()) < width) number.insert(0, width - number.size(), '0');
    const std::filesystem::path p(base);
    return (p.parent_path() / (p.stem().string() + "-" + number + p.extension().string())).string();
}

std::string frame_label(const AnimationFrame& frame) {
    return std::to_string(frame.number) + "/" + std::to_string(frame.count);
}

AnimationPlan plan_animation(const AnimationRequest& request, const std::vector<RenderJob>& jobs, const std::string& output) {
    AnimationPlan plan;
    if (jobs.empty()) return plan;
    const int count = request.orbit() ? request.orbit_frames : static_cast<int>(jobs.size());
    int first = 1, last = count;
    if (request.frames_given()) {
        if (request.last > count)
            throw InputError(request.frames_text + ": " +
                             (request.orbit() ? "--orbit-frames " + std::to_string(count) + " makes frames " + range_text(count)
                                              : "the script's gr.render calls are frames " + range_text(count)));
        first = request.first;
        last = request.last;
    }
    if (request.orbit()) {
        if (jobs.size() > 1)
            plan.warnings.push_back("--orbit-frames: the script calls gr.render " + std::to_string(jobs.size()) +
                                    " times; only the first (" + jobs[0].where.str() + ") is orbited");
        const std::string base = output.empty() ? jobs[0].output : output;
        for (int i = first; i <= last; ++i)
            plan.frames.push_back({jobs[0], numbered_frame_path(base, i, count), i, count, 0, output.empty()});
        plan.needs_target = true;
    } else {
        for (int i = first; i <= last; ++i)
            plan.frames.push_back(
                {jobs[i - 1], script_frame_path(output, jobs[i - 1], i - 1, jobs.size()), i, count, i - 1, output.empty()});
    }
    return plan;
}

void aim_orbit(AnimationPlan& plan, double target_distance) {
    if (!plan.needs_target) return;
    for (AnimationFrame& frame : plan.frames) {
        const CameraDesc& script = frame.job.camera;
        const double distance = target_distance > 0.0 && std::isfinite(target_distance) ? target_distance
                                                                                          : default_target_distance(script);
        frame.job.camera = orbit_frame_camera(script, distance, frame.number, frame.count);
    }
    plan.needs_target = false;
}

AnimationPlan plan_frames(const AnimationRequest& request, const std::vector<RenderJob>& jobs, const std::string& output,
                          const TargetDistance& target) {
    AnimationPlan plan = plan_animation(request, jobs, output);
    if (plan.needs_target) aim_orbit(plan, target ? target(jobs[0]) : 0.0);
    return plan;
}

}  // namespace caustica
