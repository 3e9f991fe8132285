// Planning `caustica render`: parsing its arguments, running the script, planning the frames,
// checking every output before any rendering, and finding the orbit's target.
#include "app/render_plan.h"

#include "app/render_command.h"
#include "app/render_interrupt.h"
#include "core/io/atomic_file.h"
#include "core/io/image_io.h"
#include "core/lua/scene_loader.h"
#include "core/render/orbit_target.h"
#include "core/render/render_session.h"
#include "core/util/printable_text.h"

#include <cstdio>
#include <filesystem>
#include <new>
#include <set>
#include <stdexcept>
#include <unistd.h>

namespace caustica {
namespace {

RenderArguments parse_arguments(const std::vector<std::string>& args) {
    RenderArguments parsed;
    std::vector<std::string> tokens;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-h" || a == "--help") {
            parsed.help = true;
        } else if (a == "-o" || a == "--output") {
            if (i + 1 >= args.size()) throw InputError(a + ": expects a file name");
            parsed.output = args[++i];
        } else if (a.rfind("--output=", 0) == 0) {
            parsed.output = a.substr(9);
        } else if (a == "--allow-read") {
            if (i + 1 >= args.size()) throw InputError(a + ": expects a folder");
            parsed.allow_read.push_back(args[++i]);
        } else if (a.rfind("--allow-read=", 0) == 0) {
            parsed.allow_read.push_back(a.substr(13));
        } else if (a == "--resume") {
            parsed.resume = true;
        } else {
            tokens.push_back(a);
        }
    }
    if (parsed.help) return parsed;
    parsed.animation = take_animation_arguments(tokens);
    std::vector<std::string> positional;
    Options check;
    apply_option_tokens(check, tokens, &positional);  // validates every option before any work
    if (positional.empty()) throw InputError("render: no scene file given (usage: caustica render [options] SCENE.lua)");
    if (positional.size() > 1) throw InputError("render: one scene at a time, got '" + positional[0] + "' and '" + positional[1] + "'");
    parsed.scene = positional[0];
    for (const std::string& t : tokens)
        if (t != parsed.scene) parsed.option_tokens.push_back(t);
    if (!parsed.output.empty() && !image_format_of(parsed.output))
        throw InputError("-o " + parsed.output + ": the output must end in .png, .exr or .pfm");
    return parsed;
}

/// Refuses, before any rendering, an output that cannot be written. A bad name is the scene's
/// error (exit 2), and so is a script's name that leads outside the current folder through a
/// symlink (docs/RELIABILITY.md, section 1; the write checks it again); a missing or unwritable
/// folder is the environment's, exit 1 like a write that fails after rendering (README, exit
/// codes). Also removes stale temporaries of killed runs, once per folder (`cleaned` holds the
/// folders done: an animation writes many frames to one folder).
void check_writable(const std::string& path, const RenderJob& job, bool from_command_line, std::set<std::string>& cleaned) {
    std::filesystem::path p(path);
    if (!image_format_of(path))
        throw InputError(job.where, "gr.render: output '" + path + "' must end in .png, .exr or .pfm");
    if (!from_command_line)
        if (const std::string outside = output_outside_current_folder(path); !outside.empty())
            throw output_outside(job, outside);
    const std::string prefix = from_command_line ? "-o: cannot write '" + path + "': "
                                                 : job.where.str() + ": gr.render: cannot write '" + path + "': ";
    std::filesystem::path dir = p.parent_path().empty() ? std::filesystem::path(".") : p.parent_path();
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(dir, ec);
    if (ec && ec != std::errc::no_such_file_or_directory)  // a symlink loop, a name too long, ...
        throw std::runtime_error(prefix + "folder '" + dir.string() + "': " + ec.message());
    if (!std::filesystem::is_directory(status))
        throw std::runtime_error(prefix + (std::filesystem::exists(status) ? "'" + dir.string() + "' is not a folder"
                                                                           : "folder '" + dir.string() + "' does not exist"));
    if (::access(dir.c_str(), W_OK) != 0)
        throw std::runtime_error(prefix + "folder '" + dir.string() + "' is not writable");
    if (const std::string problem = output_file_problem(path); !problem.empty()) throw std::runtime_error(prefix + problem);
    if (cleaned.insert(dir.string()).second) remove_stale_output_temporaries(dir.string());
}

/// "W x H" as a job will render it.
std::string job_size(const RenderJob& job) {
    const int r = job.options.resolution_override;
    return std::to_string(r ? r : job.width) + " x " + std::to_string(r ? r : job.height);
}

/// The distance from the eye of `job`, along its view, to the centre of what it sees (0 when it
/// sees nothing): the target --orbit-frames turns around, found as the preview finds its orbit's
/// target (visible_centre_distance). Builds the scene, which the frames then reuse (the session
/// caches it by its geometry's fingerprint). Rethrows scene errors.
double view_axis_target(RenderSession& session, const RenderJob& job) {
    session.set_job(job);
    session.prepare_geometry();
    const int r = job.options.resolution_override;
    return visible_centre_distance(session, job.camera, r ? r : job.width, r ? r : job.height);
}

}  // namespace

InputError output_outside(const RenderJob& job, const std::string& reason) {
    return InputError(job.where, "gr.render: output " + reason +
                                     " (scenes write below the current folder; use -o to choose another place)");
}

InputError out_of_memory(const RenderJob& job, const std::string& path) {
    // The scene asks for more than the machine can hold: a scene error (exit 2, README).
    return InputError(job.where, "gr.render: not enough memory to render '" + path + "' (" + job_size(job) +
                                     " pixels); lower the resolution or the photon count");
}

int plan_render(const std::vector<std::string>& args, RenderSession& session, bool writes, RenderPlan& out) {
    RenderArguments& parsed = out.parsed;
    parsed = parse_arguments(args);
    if (parsed.help) {
        if (writes) std::printf("%s", render_help().c_str());
        return exit_ok;
    }
    Options command_line;
    apply_option_tokens(command_line, parsed.option_tokens);
    if (!std::filesystem::is_regular_file(parsed.scene))
        throw InputError(parsed.scene + ": no such scene file");

    LoadSettings settings;
    settings.timeout_seconds = command_line.script_timeout;
    settings.memory_limit_bytes = static_cast<std::size_t>(command_line.script_memory_mib) << 20;
    settings.allow_read = parsed.allow_read;
    settings.output_given = !parsed.output.empty();
    settings.cancel = &interrupted;
    SceneScript script;
    try {
        script = load_scene_script(parsed.scene, settings);
    } catch (const ScriptCancelled&) {
        if (writes) std::fprintf(stderr, "caustica: interrupted while running %s\n", printable_text(parsed.scene).c_str());
        return exit_interrupted;
    } catch (const std::bad_alloc&) {
        throw InputError(parsed.scene + ": not enough memory to run the script");
    }
    if (writes && !command_line.silent)
        for (const std::string& w : script.warnings) std::fprintf(stderr, "warning: %s\n", printable_text(w).c_str());
    if (script.renders.empty()) throw InputError(parsed.scene + ": the script calls no gr.render; nothing to render");

    // The command line wins over gr.option: re-apply its tokens on top of each job's options.
    std::vector<RenderJob> jobs = script.renders;
    for (RenderJob& job : jobs) {
        job.apply_command_line(parsed.option_tokens);
        if (!writes) job.options.silent = true;  // under mpirun rank 0 speaks for every rank
    }
    // The frames: every gr.render, or --frames of them, or --orbit-frames views of the first.
    out.plan = plan_animation(parsed.animation, jobs, parsed.output);
    if (writes) {
        std::set<std::string> cleaned;
        for (const AnimationFrame& frame : out.plan.frames) {
            if (interrupted) {  // 100000 frames take seconds to check
                std::fprintf(stderr, "caustica: interrupted; no frame written\n");
                return exit_interrupted;
            }
            check_writable(frame.path, frame.job, !parsed.output.empty(), cleaned);
        }
    }
    for (const AnimationFrame& frame : out.plan.frames) {
        const Options& o = frame.job.options;
        check_render_stop_rules(o);
        check_shown_layer(o);
        if (const std::string why = o.layers ? layers_refusal(o, frame.path) : std::string(); !why.empty())
            throw parsed.output.empty() ? InputError(frame.job.where, "gr.render: " + why) : InputError(why);
    }
    if (parsed.resume)
        for (const AnimationFrame& frame : out.plan.frames) {
            if (frame.job.options.layers)
                throw InputError("--resume: a saved accumulation holds no layers; render --layers without --resume");
            if (!frame.job.options.accumulates())
                throw InputError("--resume: " + frame.path +
                                 " does not accumulate passes; it continues --integrator progressive with --passes, "
                                 "--time or --target-error");
        }
    if (writes && !jobs[0].options.silent)
        for (const std::string& w : out.plan.warnings) std::fprintf(stderr, "warning: %s\n", printable_text(w).c_str());
    // Frames are numbered in the images' metadata when there is more than one to number.
    out.numbered = parsed.animation.any() || jobs.size() > 1;
    if (out.plan.needs_target) {
        double distance = 0.0;
        try {
            distance = view_axis_target(session, jobs[0]);
        } catch (const std::bad_alloc&) {
            throw out_of_memory(jobs[0], out.plan.frames.front().path);
        }
        if (interrupted) {
            if (writes && !jobs[0].options.silent) std::fprintf(stderr, "caustica: interrupted; no frame written\n");
            return exit_interrupted;
        }
        aim_orbit(out.plan, distance);
    }
    return -1;
}

}  // namespace caustica
