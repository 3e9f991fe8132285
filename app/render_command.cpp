#include "app/render_command.h"

#include "core/integrators/registry.h"

#include "app/animation.h"
#include "app/progress_bar.h"
#include "core/lua/scene_loader.h"
#include "core/io/image_io.h"
#include "core/io/png_io.h"
#include "core/render/random.h"
#include "core/render/render_session.h"
#include "core/scene/camera.h"
#include "core/scene/source_location.h"
#include "core/render/cluster.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <new>
#include <optional>
#include <random>
#include <set>

#include <tbb/info.h>
#include <stdexcept>
#include <thread>
#include <unistd.h>

namespace caustica {
namespace {

std::atomic<bool> interrupted{false};

/// The first Ctrl-C or SIGTERM asks every stage to stop (within a second); a second one leaves at
/// once, removing the temporary of an image being written (PNG, EXR or PFM) so that nothing
/// partial stays behind.
extern "C" void on_interrupt(int) {
    if (!interrupted.exchange(true)) return;
    remove_output_temporaries_from_signal_handler();
    ::_exit(exit_interrupted);
}

struct RenderArguments {
    std::vector<std::string> option_tokens;  ///< everything but the scene and -o
    std::string scene;
    std::string output;                       ///< -o, or "" for the names the script gives
    std::vector<std::string> allow_read;      ///< --allow-read folders (command line only)
    AnimationRequest animation;               ///< --frames, --orbit-frames (command line only)
    bool help = false;
};

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
/// error (exit 2); a missing or unwritable folder is the environment's, exit 1 like a write that
/// fails after rendering (README, exit codes). Also removes stale temporaries of killed runs, once
/// per folder (`cleaned` holds the folders done: an animation writes many frames to one folder).
void check_writable(const std::string& path, const RenderJob& job, bool from_command_line, std::set<std::string>& cleaned) {
    std::filesystem::path p(path);
    if (!image_format_of(path))
        throw InputError(job.where, "gr.render: output '" + path + "' must end in .png, .exr or .pfm");
    const std::string prefix = from_command_line ? "-o: cannot write '" + path + "': "
                                                 : job.where.str() + ": gr.render: cannot write '" + path + "': ";
    std::filesystem::path dir = p.parent_path().empty() ? std::filesystem::path(".") : p.parent_path();
    std::error_code ec;
    if (!std::filesystem::is_directory(dir))
        throw std::runtime_error(prefix + (std::filesystem::exists(dir, ec) ? "'" + dir.string() + "' is not a folder"
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

/// printf into a string.
[[gnu::format(printf, 2, 3)]] void appendf(std::string& out, const char* format, ...) {
    char line[512];
    va_list args;
    va_start(args, format);
    const int n = std::vsnprintf(line, sizeof line, format, args);
    va_end(args);
    if (n > 0) out.append(line, static_cast<std::size_t>(std::min<int>(n, sizeof line - 1)));
}

/// What -t and -S print for a render (text, so that a rank can send it to rank 0).
std::string stats_text(const RenderStats& stats, bool timing, bool statistics) {
    std::string out;
    if (timing) {
        appendf(out, "stage times:\n");
        for (const StageTime& s : stats.stages)
            appendf(out, "  %-22s %9.3f s%s\n", s.name.c_str(), s.seconds, s.cached ? "  (cached)" : "");
        appendf(out, "  %-22s %9.3f s\n", "total", stats.total_seconds);
    }
    if (statistics) {
        const RayCounters& r = stats.rays;
        const double seconds = stats.total_seconds > 0 ? stats.total_seconds : 1e-9;
        appendf(out, "statistics:\n");
        appendf(out, "  integrator             %9s\n", stats.integrator.c_str());
        appendf(out, "  threads                %9d\n", stats.threads);
        appendf(out, "  analytic primitives    %9zu\n", stats.scene.analytic_primitives);
        appendf(out, "  mesh instances         %9zu (%zu meshes, %zu triangles stored, %zu in the world)\n",
                     stats.scene.mesh_instances, stats.scene.unique_meshes, stats.scene.triangles_stored, stats.scene.triangles_instanced);
        appendf(out, "  CSG objects            %9zu (%zu primitives inside)\n", stats.scene.csg_objects, stats.scene.csg_leaves);
        appendf(out, "  camera samples         %9llu\n", static_cast<unsigned long long>(r.samples));
        appendf(out, "  anti-aliased pixels    %9llu\n", static_cast<unsigned long long>(r.supersampled_pixels));
        appendf(out, "  rays: primary          %9llu\n", static_cast<unsigned long long>(r.primary));
        appendf(out, "        shadow           %9llu\n", static_cast<unsigned long long>(r.shadow));
        appendf(out, "        reflected        %9llu\n", static_cast<unsigned long long>(r.reflected));
        appendf(out, "        refracted        %9llu\n", static_cast<unsigned long long>(r.refracted));
        appendf(out, "        total            %9llu (%.2f M rays/s)\n",
                     static_cast<unsigned long long>(r.total_rays()), r.total_rays() / seconds * 1e-6);
        for (std::size_t l = 0; l < stats.caustic_lights.size(); ++l) {
            const LightCausticStats& c = stats.caustic_lights[l];
            std::fprintf(stderr,
                         "  caustic photons, light %zu: %lld directions, %lld traced, %lld stored; projection map "
                         "%s (occupied %.1f%% of the sphere)\n",
                         l + 1, c.candidates, c.traced, c.stored, c.projection_map_used ? "used" : "not used",
                         100.0 * c.occupied_fraction);
        }
        if (stats.caustic_photons > 0)
            appendf(out, "  caustic map            %9zu photons, %.1f MiB\n", stats.caustic_photons,
                         stats.caustic_map_bytes / 1048576.0);
        for (std::size_t l = 0; l < stats.gi_lights.size(); ++l)
            appendf(out, "  GI photons, light %zu: %lld directions, %lld traced, %lld stored\n", l + 1,
                         stats.gi_lights[l].candidates, stats.gi_lights[l].traced, stats.gi_lights[l].stored);
        if (stats.gi_photons > 0)
            appendf(out, "  GI map                 %9zu photons, %.1f MiB\n", stats.gi_photons,
                         stats.gi_map_bytes / 1048576.0);
        if (r.gathers > 0)
            appendf(out, "  radiance estimates     %9llu (%.3f s summed over threads, %.0f%% of render thread time)\n",
                         static_cast<unsigned long long>(r.gathers), r.gather_seconds,
                         100.0 * r.gather_seconds / (seconds * std::max(1, stats.threads)));
        if (const RenderStats::Accumulation& a = stats.accumulation; a.passes > 0) {
            appendf(out, "  progressive passes     %9d (stopped by %s)\n", a.passes, a.stopped_by.c_str());
            appendf(out, "  photons over passes    %9lld directions\n", a.photons_emitted);
            appendf(out, "  gather radius          %9.4g first, %.4g now\n", a.first_radius, a.radius);
            if (a.error >= 0.0)
                appendf(out, "  estimated error        %9.4f relative RMSE over the caustics (noise %.4f, bias %.4f)\n",
                             a.error, a.noise, a.bias);
            else
                appendf(out, "  estimated error        %9s (needs 2 passes and a caustic)\n", "unknown");
            appendf(out, "  accumulation buffers   %9.1f MiB\n", a.bytes / 1048576.0);
        }
        if (!timing)  // -t has just printed them: once is enough
            for (const StageTime& s : stats.stages)
                appendf(out, "  time: %-16s %9.3f s%s\n", s.name.c_str(), s.seconds, s.cached ? " (cached)" : "");
    }
    return out;
}

void print_stats(const RenderStats& stats, bool timing, bool statistics) {
    std::fputs(stats_text(stats, timing, statistics).c_str(), stderr);
}

/// How the job's options write its image (--srgb, --tonemap, --exposure, --exr-pixel).
ImageWriteSettings write_settings(const Options& o) {
    ImageWriteSettings settings;
    settings.encoding = o.srgb ? PixelEncoding::srgb : PixelEncoding::clamped_linear;
    settings.tonemap = o.tonemap;
    settings.exposure_stops = static_cast<float>(o.exposure);
    settings.exr_pixel = o.exr_pixel;
    return settings;
}

std::string format_vector(const glm::dvec3& v) {
    char text[96];
    std::snprintf(text, sizeof text, "%.9g %.9g %.9g", v.x, v.y, v.z);
    return text;
}

/// The PNG text chunks / EXR string attributes of a rendered image: what made it (the keys of
/// docs/OUTPUT.md; the preview's save writes the same ones, ui/save_image.cpp).
ImageMetadata render_metadata(const RenderJob& job, const std::string& scene_path, const RenderStats& stats,
                              const std::string& frame) {
    const Options& o = job.options;
    const CameraDesc& c = job.camera;
    char seconds[32], fovy[32];
    std::snprintf(seconds, sizeof seconds, "%.3f", stats.total_seconds);
    std::snprintf(fovy, sizeof fovy, "%.9g", c.fovy_degrees);
    const int r = o.resolution_override;
    ImageMetadata text = {{"Software", "caustica " CAUSTICA_VERSION},
                          {"Source", scene_path},
                          {"caustica:integrator", integrator_entry(o.integrator).name},
                          {"caustica:options", describe_non_default(o)},
                          {"caustica:camera", "eye " + format_vector(c.eye) + " view " + format_vector(c.view) + " up " +
                                                  format_vector(c.up) + " fovy " + fovy},
                          {"caustica:size", std::to_string(r ? r : job.width) + "x" + std::to_string(r ? r : job.height)},
                          {"caustica:render-seconds", seconds}};
    if (!frame.empty()) text.push_back({"caustica:frame", frame});
    if (const RenderStats::Accumulation& a = stats.accumulation; a.passes > 0) {
        text.push_back({"caustica:passes", std::to_string(a.passes)});
        text.push_back({"caustica:photons", std::to_string(a.photons_emitted)});
        if (a.error >= 0.0) {
            char error[32];
            std::snprintf(error, sizeof error, "%.4f", a.error);
            text.push_back({"caustica:estimated-error", error});
        }
    }
    return text;
}

/// Renders one job to completion (or interruption), showing its progress when `show`. Returns
/// exit_ok or exit_interrupted; rethrows the session's errors.
int render_frame(RenderSession& session, const RenderJob& job, const std::string& path, bool show) {
    const Options& o = job.options;
    session.set_job(job);
    if (o.verbose && !o.silent)
        std::fprintf(stderr, "%s: rendering %s (%d x %d)\n", job.where.str().c_str(), path.c_str(),
                     o.resolution_override ? o.resolution_override : job.width,
                     o.resolution_override ? o.resolution_override : job.height);
    session.start();
    ProgressBar bar(show && !o.silent);
    for (;;) {
        const SessionProgress p = session.progress();
        if (!p.running) break;
        if (interrupted) session.cancel();
        if (p.accumulating) {
            // Passes have no fixed total: the nearest stopping rule gives the fraction.
            double fraction = 0.0;
            if (o.pass_limit() > 0) fraction = std::max(fraction, double(p.passes_done) / o.pass_limit());
            if (o.time_limit > 0.0) fraction = std::max(fraction, p.elapsed_seconds / o.time_limit);
            if (o.target_error > 0.0 && p.error.known)
                fraction = std::max(fraction, std::min(1.0, o.target_error / p.error.relative));
            char status[160];
            if (p.error.known)
                std::snprintf(status, sizeof status, "pass %d, %.3g photons, estimated error %.1f%%", p.passes_done,
                              double(p.photons_emitted), 100.0 * p.error.relative);
            else
                std::snprintf(status, sizeof status, "pass %d, %.3g photons", p.passes_done, double(p.photons_emitted));
            bar.update(std::min(1.0, fraction), p.elapsed_seconds, status);
        } else {
            bar.update(p.tiles_total ? double(p.tiles_done) / double(p.tiles_total) : 0.0, p.elapsed_seconds, p.stage);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    bar.finish();
    const bool complete = session.wait();  // rethrows scene errors found while preparing
    if (show && !o.silent)
        for (const std::string& w : session.warnings()) std::fprintf(stderr, "warning: %s\n", w.c_str());
    return complete && !interrupted ? exit_ok : exit_interrupted;
}

/// Writes a rendered frame and reports it (-t/-S: `stats`, or the text another rank made of
/// its own). Returns an exit code (write errors throw).
int write_frame(const RenderJob& job, const std::string& scene_path, const std::string& path, const std::string& frame,
                const Image& image, const RenderStats& stats, const std::string* stats_from_rank = nullptr) {
    const Options& o = job.options;
    try {
        write_image_atomic(path, image, write_settings(o), render_metadata(job, scene_path, stats, frame), &interrupted);
    } catch (const ImageWriteCancelled&) {
        if (!o.silent) std::fprintf(stderr, "caustica: interrupted; %s not written\n", path.c_str());
        return exit_interrupted;
    }
    if (stats_from_rank)
        std::fputs(stats_from_rank->c_str(), stderr);
    else
        print_stats(stats, o.timing, o.stats);
    if (!o.silent) std::printf("wrote %s (%d x %d, %.2f s)\n", path.c_str(), image.width, image.height, stats.total_seconds);
    return exit_ok;
}

/// Renders one job and writes its image.
int render_job(RenderSession& session, const RenderJob& job, const std::string& scene_path, const std::string& path,
               const std::string& frame) {
    if (render_frame(session, job, path, true) != exit_ok) {
        if (!job.options.silent) std::fprintf(stderr, "caustica: interrupted; %s not written\n", path.c_str());
        return exit_interrupted;
    }
    return write_frame(job, scene_path, path, frame, session.image(), session.stats());
}

/// The distance from the eye of `job` to the first surface its central view ray hits (0 when it
/// hits nothing): the target --orbit-frames turns around, found as the preview finds its orbit's
/// target. Builds the scene, which the frames then reuse (the session caches it by its geometry's
/// fingerprint). Rethrows scene errors.
double view_axis_target(RenderSession& session, const RenderJob& job) {
    session.set_job(job);
    session.prepare_geometry();
    const int r = job.options.resolution_override;
    const int width = r ? r : job.width, height = r ? r : job.height;
    const Camera camera(job.camera, width, height);
    glm::vec3 point;
    if (!session.pick(camera.generate(0.5f * width, 0.5f * height), point)) return 0.0;
    return glm::length(glm::dvec3(point) - job.camera.eye);
}

InputError out_of_memory(const RenderJob& job, const std::string& path) {
    // The scene asks for more than the machine can hold: a scene error (exit 2, README).
    return InputError(job.where, "gr.render: not enough memory to render '" + path + "' (" + job_size(job) +
                                     " pixels); lower the resolution or the photon count");
}

/// What a render command renders, once its arguments, script and frames are checked.
struct RenderPlan {
    RenderArguments parsed;
    AnimationPlan plan;
    bool numbered = false;  ///< frames are numbered in the images' metadata
};

/// Everything before rendering: arguments, the script, the frames, the outputs (checked where
/// they are written: `writes`), the orbit's target. Returns an exit code to end with at once
/// (help, interrupted), or -1 to render.
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
        if (writes) std::fprintf(stderr, "caustica: interrupted while running %s\n", parsed.scene.c_str());
        return exit_interrupted;
    } catch (const std::bad_alloc&) {
        throw InputError(parsed.scene + ": not enough memory to run the script");
    }
    if (writes && !command_line.silent)
        for (const std::string& w : script.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
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
        if (integrator_entry(o.integrator).accumulates && o.passes == 0 && o.time_limit <= 0.0 && o.target_error <= 0.0)
            throw InputError("--passes 0 renders until another rule stops it: give --time or --target-error too");
    }
    if (writes && !jobs[0].options.silent)
        for (const std::string& w : out.plan.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
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

/// Rank 0 tells the user what stopped every rank (an interruption once: `said` when it was);
/// every rank exits with its code.
int report(const RankFailure& failure, const Cluster& cluster, bool said = false) {
    if (cluster.rank() == 0) {
        if (failure.exit_code == exit_interrupted) {
            if (!said) std::fprintf(stderr, "caustica: interrupted; nothing more written\n");
        } else if (failure.rank == 0) {
            std::fprintf(stderr, "caustica: %s\n", failure.message.c_str());
        } else {
            std::fprintf(stderr, "caustica: rank %d of %d: %s\n", failure.rank, cluster.size(), failure.message.c_str());
        }
    }
    return failure.exit_code;
}

/// A rendered frame as bytes for rank 0, and back: the image, what its metadata reports and
/// what -t/-S print about it.
Cluster::Bytes frame_bytes(const Image& image, const RenderStats& stats, const std::string& text) {
    Cluster::Bytes bytes;
    auto put = [&](const void* p, std::size_t n) {
        bytes.insert(bytes.end(), static_cast<const std::uint8_t*>(p), static_cast<const std::uint8_t*>(p) + n);
    };
    const std::int32_t size[2] = {image.width, image.height};
    put(size, sizeof size);
    const double numbers[5] = {stats.total_seconds, static_cast<double>(stats.accumulation.passes),
                               static_cast<double>(stats.accumulation.photons_emitted), stats.accumulation.error,
                               static_cast<double>(stats.threads)};
    put(numbers, sizeof numbers);
    put(image.pixels.data(), image.pixels.size() * sizeof(glm::vec3));
    put(text.data(), text.size());
    return bytes;
}

void frame_of(const Cluster::Bytes& bytes, Image& image, RenderStats& stats, std::string& text) {
    std::int32_t size[2];
    double numbers[5];
    if (bytes.size() < sizeof size + sizeof numbers) throw std::runtime_error("a frame from another rank is truncated");
    std::memcpy(size, bytes.data(), sizeof size);
    std::memcpy(numbers, bytes.data() + sizeof size, sizeof numbers);
    const std::size_t pixels = static_cast<std::size_t>(std::max(0, size[0])) * static_cast<std::size_t>(std::max(0, size[1]));
    const std::size_t image_end = sizeof size + sizeof numbers + pixels * sizeof(glm::vec3);
    if (bytes.size() < image_end) throw std::runtime_error("a frame from another rank has the wrong size");
    image = Image(size[0], size[1]);
    std::memcpy(image.pixels.data(), bytes.data() + sizeof size + sizeof numbers, pixels * sizeof(glm::vec3));
    text.assign(bytes.begin() + static_cast<std::ptrdiff_t>(image_end), bytes.end());
    stats = RenderStats{};
    stats.total_seconds = numbers[0];
    stats.accumulation.passes = static_cast<int>(numbers[1]);
    stats.accumulation.photons_emitted = static_cast<long long>(numbers[2]);
    stats.accumulation.error = numbers[3];
    stats.threads = static_cast<int>(numbers[4]);
}

/// This rank's failure from a caught exception, with out-of-memory named as a scene error.
std::optional<RankFailure> failure_here(std::exception_ptr error, const Cluster& cluster, const AnimationFrame* frame) {
    if (!error) return std::nullopt;
    try {
        std::rethrow_exception(error);
    } catch (const std::bad_alloc&) {
        if (frame) return failure_of(std::make_exception_ptr(out_of_memory(frame->job, frame->path)), cluster.rank());
    } catch (...) {
    }
    return failure_of(error, cluster.rank());
}

/// What every rank must render alike: each frame's job by content (computed once per gr.render:
/// a scene's meshes are hashed whole) and its camera (orbit frames differ by it alone).
std::uint64_t plan_fingerprint(const AnimationPlan& plan) {
    std::uint64_t fingerprint = plan.frames.size();
    std::map<int, std::uint64_t> by_job;
    for (const AnimationFrame& frame : plan.frames) {
        auto [it, fresh] = by_job.try_emplace(frame.job_index, 0);
        if (fresh) it->second = job_content_fingerprint(frame.job);
        fingerprint = hash_combine(fingerprint, it->second);
        const CameraDesc& c = frame.job.camera;
        for (double v : {c.eye.x, c.eye.y, c.eye.z, c.view.x, c.view.y, c.view.z, c.up.x, c.up.y, c.up.z, c.fovy_degrees})
            fingerprint = hash_double(fingerprint, v);
    }
    return fingerprint;
}

/// -j as the frames have it (0: every core the process may use).
int command_line_threads(const RenderPlan& plan) { return plan.plan.frames.front().job.options.threads; }

/// Under mpirun: the frames rendered by every rank together (a frame at a time: fewer frames than
/// ranks), or whole frames shared out in rounds of one per rank. Rank 0 writes every file.
int render_with_ranks(Cluster& cluster, RenderSession& session, const RenderPlan& plan) {
    const std::vector<AnimationFrame>& frames = plan.plan.frames;
    const bool root = cluster.rank() == 0;
    const int ranks = cluster.size();
    auto label = [&](const AnimationFrame& f) { return plan.numbered ? frame_label(f) : std::string(); };
    if (static_cast<int>(frames.size()) <= ranks) {
        session.set_cluster(&cluster);
        for (const AnimationFrame& frame : frames) {
            // Every rank renders; once every rank says it finished, rank 0 writes (an interruption
            // anywhere before that writes nothing).
            std::exception_ptr error;
            int code = exit_ok;
            try {
                code = render_frame(session, frame.job, frame.path, root);
            } catch (...) {
                error = std::current_exception();
            }
            std::optional<RankFailure> mine = failure_here(error, cluster, &frame);
            if (!mine && code != exit_ok) mine = RankFailure{cluster.rank(), code, "interrupted"};
            if (const std::optional<RankFailure> failure = cluster.agree(mine)) {
                if (root && failure->exit_code == exit_interrupted && !frame.job.options.silent)
                    std::fprintf(stderr, "caustica: interrupted; %s not written\n", frame.path.c_str());
                return report(*failure, cluster, true);
            }
            mine.reset();
            if (root) {
                try {
                    code = write_frame(frame.job, plan.parsed.scene, frame.path, label(frame), session.image(),
                                       session.stats());
                } catch (...) {
                    mine = failure_here(std::current_exception(), cluster, nullptr);
                }
                if (!mine && code != exit_ok) mine = RankFailure{0, code, "interrupted"};
            }
            if (const std::optional<RankFailure> failure = cluster.agree(mine)) return report(*failure, cluster, true);
        }
        return exit_ok;
    }
    // More frames than ranks: each renders whole frames alone, rank k frames k, k + K, ...
    session.set_cluster(nullptr);
    const std::size_t count = frames.size();
    for (std::size_t round = 0; round * static_cast<std::size_t>(ranks) < count; ++round) {
        const std::size_t mine_index = round * static_cast<std::size_t>(ranks) + static_cast<std::size_t>(cluster.rank());
        Cluster::Bytes result;
        std::exception_ptr error;
        int code = exit_ok;
        if (mine_index < count) {
            const AnimationFrame& frame = frames[mine_index];
            try {
                code = render_frame(session, frame.job, frame.path, root);
                const RenderStats stats = session.stats();
                if (code == exit_ok)
                    result = frame_bytes(session.image(), stats, stats_text(stats, frame.job.options.timing, frame.job.options.stats));
            } catch (...) {
                error = std::current_exception();
            }
        }
        std::optional<RankFailure> mine = failure_here(error, cluster, mine_index < count ? &frames[mine_index] : nullptr);
        if (!mine && code != exit_ok) mine = RankFailure{cluster.rank(), code, "interrupted"};
        if (const std::optional<RankFailure> failure = cluster.agree(mine)) return report(*failure, cluster);
        const std::vector<Cluster::Bytes> results = cluster.gather(result);
        mine.reset();
        code = exit_ok;
        if (root) {
            try {
                for (std::size_t r = 0; r < results.size() && round * ranks + r < count && code == exit_ok; ++r) {
                    const AnimationFrame& frame = frames[round * static_cast<std::size_t>(ranks) + r];
                    Image image;
                    RenderStats stats;
                    std::string text;
                    frame_of(results[r], image, stats, text);
                    code = write_frame(frame.job, plan.parsed.scene, frame.path, label(frame), image, stats, &text);
                }
            } catch (...) {
                mine = failure_here(std::current_exception(), cluster, nullptr);
            }
            if (!mine && code != exit_ok) mine = RankFailure{0, code, "interrupted"};
        }
        if (const std::optional<RankFailure> failure = cluster.agree(mine)) return report(*failure, cluster);
    }
    return exit_ok;
}

}  // namespace

std::string render_help() {
    return "usage: caustica render [options] SCENE.lua [-o OUT.png|OUT.exr|OUT.pfm]\n"
           "\n"
           "Runs the scene script and renders every gr.render it calls. Without -o each render\n"
           "writes the file the script names, relative to the current folder; with -o a single\n"
           "render writes OUT.png and several write OUT-1.png, OUT-2.png, ...\n"
           "Animations (docs/ANIMATION.md; command line only):\n"
           "  --frames A:B       render frames A to B only (numbered from 1; --frames N: frame N);\n"
           "                     without --orbit-frames the frames are the script's gr.render calls\n"
           "  --orbit-frames N   N frames of the first gr.render, its camera turned 360 degrees about\n"
           "                     its up vector around the first surface on its view axis; written as\n"
           "                     OUT-0001.png ... (or the script's name with -0001 before the extension)\n"
           "The extension picks the format: .png (8-bit; --srgb, --tonemap), .exr (OpenEXR, linear\n"
           "and unclamped, half or --exr-pixel float, parameters in the header) or .pfm (linear float).\n"
           "--exposure scales every format. docs/OUTPUT.md has the details.\n"
           "The script runs sandboxed: it reads only regular files under its own folder, and\n"
           "--allow-read DIR (repeatable, command line only) lets it read under DIR too.\n"
           "Script names for gr.render are relative to the current folder, without '..'.\n"
           "Options may also be set in the scene with gr.option('--flag ...'); the command line wins.\n"
           "Exit codes: 0 success, 1 output could not be written (a missing or unwritable folder, found\n"
           "before or after rendering), 2 scene or usage error (a scene that needs more memory than\n"
           "there is included), 130 interrupted (nothing written).\n" +
           options_help();
}

int run_render_command(const std::vector<std::string>& args, Cluster* cluster) {
    if (cluster && cluster->size() <= 1) cluster = nullptr;
    const bool root = !cluster || cluster->rank() == 0;
    std::signal(SIGINT, on_interrupt);
    std::signal(SIGTERM, on_interrupt);
    RenderSession session;
    RenderPlan plan;
    if (!cluster) {
        const int early = plan_render(args, session, true, plan);
        if (early >= 0) return early;
        for (const AnimationFrame& frame : plan.plan.frames) {
            int code = exit_ok;
            try {
                code = render_job(session, frame.job, plan.parsed.scene, frame.path,
                                  plan.numbered ? frame_label(frame) : "");
            } catch (const std::bad_alloc&) {
                throw out_of_memory(frame.job, frame.path);
            }
            if (code != exit_ok) return code;
        }
        return exit_ok;
    }
    // Under mpirun every rank plans the same frames from the same script; a rank that cannot
    // stops them all, with its message.
    int early = -1;
    std::exception_ptr error;
    try {
        early = plan_render(args, session, root, plan);
    } catch (...) {
        error = std::current_exception();
    }
    std::optional<RankFailure> mine = failure_here(error, *cluster, nullptr);
    if (!mine && early == exit_interrupted) mine = RankFailure{cluster->rank(), exit_interrupted, "interrupted"};
    if (const std::optional<RankFailure> failure = cluster->agree(mine)) return report(*failure, *cluster);
    // --help ends every rank, which must all have been given it (mpirun's MPMD form may not).
    const long long ending = cluster->all_sum(early >= 0 ? 1 : 0);
    if (ending == cluster->size()) return early;
    mine.reset();
    if (ending > 0 && early >= 0)
        mine = RankFailure{cluster->rank(), exit_usage, "this rank was given --help while the others render: give every rank the same arguments"};
    if (const std::optional<RankFailure> failure = cluster->agree(mine)) return report(*failure, *cluster);
    // Every rank must render the same jobs: the same binary on the same files with the same
    // options. A rank that loaded something else (a node with other files) says so.
    const std::uint64_t fingerprint = plan_fingerprint(plan.plan);
    Cluster::Bytes first_fingerprint(sizeof fingerprint);
    std::memcpy(first_fingerprint.data(), &fingerprint, sizeof fingerprint);
    cluster->broadcast(first_fingerprint, 0);
    std::uint64_t rank0_fingerprint = 0;
    std::memcpy(&rank0_fingerprint, first_fingerprint.data(), sizeof rank0_fingerprint);
    mine.reset();
    if (rank0_fingerprint != fingerprint)
        mine = RankFailure{cluster->rank(), exit_usage,
                           plan.parsed.scene + ": this rank's scene, options or files differ from rank 0's (every rank "
                           "must run the same caustica on the same files with the same options)"};
    if (const std::optional<RankFailure> failure = cluster->agree(mine)) return report(*failure, *cluster);
    // mpirun binds each rank to cores (to one core when it starts two or fewer): say so when a
    // rank gets fewer cores than its share of this machine.
    if (root && command_line_threads(plan) == 0 && !plan.plan.frames.front().job.options.silent) {
        const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
        const int here = local ? std::max(1, std::atoi(local)) : 1;
        const int usable = tbb::info::default_concurrency();
        const unsigned machine = std::thread::hardware_concurrency();
        if (machine > 0 && static_cast<unsigned>(usable * here) < machine)
            std::fprintf(stderr,
                         "warning: each rank renders on %d of this machine's %u cores (mpirun binds ranks to cores; "
                         "with fewer ranks than cores add --bind-to none, or --map-by node:PE=N)\n",
                         usable, machine);
    }
    // The ranks share their random streams: without --reproducible rank 0 draws the seed (the
    // images' options then record it: the render can be repeated).
    Cluster::Bytes seed(sizeof(std::uint64_t));
    if (root) {
        const std::uint64_t drawn = (static_cast<std::uint64_t>(std::random_device{}()) << 32) ^ std::random_device{}();
        std::memcpy(seed.data(), &drawn, sizeof drawn);
    }
    cluster->broadcast(seed, 0);
    std::uint64_t shared_seed = 0;
    std::memcpy(&shared_seed, seed.data(), sizeof shared_seed);
    for (AnimationFrame& frame : plan.plan.frames) {
        Options& o = frame.job.options;
        if (o.reproducible) continue;
        o.reproducible = true;
        o.seed = static_cast<long long>(shared_seed & 0x7fffffffffffULL);
    }
    return render_with_ranks(*cluster, session, plan);
}

}  // namespace caustica
