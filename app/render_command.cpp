#include "app/render_command.h"

#include "app/progress_bar.h"
#include "core/lua/scene_loader.h"
#include "core/io/image_io.h"
#include "core/io/png_io.h"
#include "core/render/render_session.h"
#include "core/scene/source_location.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <new>
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
    remove_png_temporaries_from_signal_handler();
    ::_exit(exit_interrupted);
}

struct RenderArguments {
    std::vector<std::string> option_tokens;  ///< everything but the scene and -o
    std::string scene;
    std::string output;                       ///< -o, or "" for the names the script gives
    std::vector<std::string> allow_read;      ///< --allow-read folders (command line only)
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

/// The file a render job writes: -o (numbered when the script renders several), else the script's.
std::string output_path(const RenderArguments& args, const RenderJob& job, std::size_t index, std::size_t count) {
    if (args.output.empty()) return job.output;
    if (count == 1) return args.output;
    std::filesystem::path p(args.output);
    return (p.parent_path() / (p.stem().string() + "-" + std::to_string(index + 1) + p.extension().string())).string();
}

/// Refuses, before any rendering, an output that cannot be written. A bad name is the scene's
/// error (exit 2); a missing or unwritable folder is the environment's, exit 1 like a write that
/// fails after rendering (README, exit codes). Also removes stale temporaries of killed runs.
void check_writable(const std::string& path, const RenderJob& job, bool from_command_line) {
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
    remove_stale_png_temporaries(dir.string());
}

/// "W x H" as a job will render it.
std::string job_size(const RenderJob& job) {
    const int r = job.options.resolution_override;
    return std::to_string(r ? r : job.width) + " x " + std::to_string(r ? r : job.height);
}

void print_stats(const RenderStats& stats, bool timing, bool statistics) {
    if (timing) {
        std::fprintf(stderr, "stage times:\n");
        for (const StageTime& s : stats.stages)
            std::fprintf(stderr, "  %-22s %9.3f s%s\n", s.name.c_str(), s.seconds, s.cached ? "  (cached)" : "");
        std::fprintf(stderr, "  %-22s %9.3f s\n", "total", stats.total_seconds);
    }
    if (statistics) {
        const RayCounters& r = stats.rays;
        const double seconds = stats.total_seconds > 0 ? stats.total_seconds : 1e-9;
        std::fprintf(stderr, "statistics:\n");
        std::fprintf(stderr, "  integrator             %9s\n", stats.integrator.c_str());
        std::fprintf(stderr, "  threads                %9d\n", stats.threads);
        std::fprintf(stderr, "  analytic primitives    %9zu\n", stats.scene.analytic_primitives);
        std::fprintf(stderr, "  mesh instances         %9zu (%zu meshes, %zu triangles stored, %zu in the world)\n",
                     stats.scene.mesh_instances, stats.scene.unique_meshes, stats.scene.triangles_stored, stats.scene.triangles_instanced);
        std::fprintf(stderr, "  CSG objects            %9zu (%zu primitives inside)\n", stats.scene.csg_objects, stats.scene.csg_leaves);
        std::fprintf(stderr, "  camera samples         %9llu\n", static_cast<unsigned long long>(r.samples));
        std::fprintf(stderr, "  anti-aliased pixels    %9llu\n", static_cast<unsigned long long>(r.supersampled_pixels));
        std::fprintf(stderr, "  rays: primary          %9llu\n", static_cast<unsigned long long>(r.primary));
        std::fprintf(stderr, "        shadow           %9llu\n", static_cast<unsigned long long>(r.shadow));
        std::fprintf(stderr, "        reflected        %9llu\n", static_cast<unsigned long long>(r.reflected));
        std::fprintf(stderr, "        refracted        %9llu\n", static_cast<unsigned long long>(r.refracted));
        std::fprintf(stderr, "        total            %9llu (%.2f M rays/s)\n",
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
            std::fprintf(stderr, "  caustic map            %9zu photons, %.1f MiB\n", stats.caustic_photons,
                         stats.caustic_map_bytes / 1048576.0);
        for (std::size_t l = 0; l < stats.gi_lights.size(); ++l)
            std::fprintf(stderr, "  GI photons, light %zu: %lld directions, %lld traced, %lld stored\n", l + 1,
                         stats.gi_lights[l].candidates, stats.gi_lights[l].traced, stats.gi_lights[l].stored);
        if (stats.gi_photons > 0)
            std::fprintf(stderr, "  GI map                 %9zu photons, %.1f MiB\n", stats.gi_photons,
                         stats.gi_map_bytes / 1048576.0);
        if (r.gathers > 0)
            std::fprintf(stderr, "  radiance estimates     %9llu (%.3f s summed over threads, %.0f%% of render thread time)\n",
                         static_cast<unsigned long long>(r.gathers), r.gather_seconds,
                         100.0 * r.gather_seconds / (seconds * std::max(1, stats.threads)));
        if (const RenderStats::Accumulation& a = stats.accumulation; a.passes > 0) {
            std::fprintf(stderr, "  progressive passes     %9d (stopped by %s)\n", a.passes, a.stopped_by.c_str());
            std::fprintf(stderr, "  photons over passes    %9lld directions\n", a.photons_emitted);
            std::fprintf(stderr, "  gather radius          %9.4g first, %.4g now\n", a.first_radius, a.radius);
            if (a.error >= 0.0)
                std::fprintf(stderr, "  estimated error        %9.4f relative RMSE over the caustics (noise %.4f, bias %.4f)\n",
                             a.error, a.noise, a.bias);
            else
                std::fprintf(stderr, "  estimated error        %9s (needs 2 passes and a caustic)\n", "unknown");
            std::fprintf(stderr, "  accumulation buffers   %9.1f MiB\n", a.bytes / 1048576.0);
        }
        if (!timing)  // -t has just printed them: once is enough
            for (const StageTime& s : stats.stages)
                std::fprintf(stderr, "  time: %-16s %9.3f s%s\n", s.name.c_str(), s.seconds, s.cached ? " (cached)" : "");
    }
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
ImageMetadata render_metadata(const RenderJob& job, const std::string& scene_path, const RenderStats& stats) {
    const Options& o = job.options;
    const CameraDesc& c = job.camera;
    char seconds[32], fovy[32];
    std::snprintf(seconds, sizeof seconds, "%.3f", stats.total_seconds);
    std::snprintf(fovy, sizeof fovy, "%.9g", c.fovy_degrees);
    const int r = o.resolution_override;
    ImageMetadata text = {{"Software", "caustica " CAUSTICA_VERSION},
                          {"Source", scene_path},
                          {"caustica:integrator", o.integrator == IntegratorKind::classic ? "classic" : "progressive"},
                          {"caustica:options", describe_non_default(o)},
                          {"caustica:camera", "eye " + format_vector(c.eye) + " view " + format_vector(c.view) + " up " +
                                                  format_vector(c.up) + " fovy " + fovy},
                          {"caustica:size", std::to_string(r ? r : job.width) + "x" + std::to_string(r ? r : job.height)},
                          {"caustica:render-seconds", seconds}};
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

/// Renders one job to completion (or interruption) and writes its image. Returns an exit code.
int render_job(RenderSession& session, const RenderJob& job, const std::string& scene_path, const std::string& path) {
    const Options& o = job.options;
    session.set_job(job);
    if (o.verbose && !o.silent)
        std::fprintf(stderr, "%s: rendering %s (%d x %d)\n", job.where.str().c_str(), path.c_str(),
                     o.resolution_override ? o.resolution_override : job.width,
                     o.resolution_override ? o.resolution_override : job.height);
    session.start();
    ProgressBar bar(!o.silent);
    for (;;) {
        const SessionProgress p = session.progress();
        if (!p.running) break;
        if (interrupted) session.cancel();
        if (p.accumulating) {
            // Passes have no fixed total: the nearest stopping rule gives the fraction.
            double fraction = 0.0;
            if (o.passes > 0) fraction = std::max(fraction, double(p.passes_done) / o.passes);
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
    if (!o.silent)
        for (const std::string& w : session.warnings()) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (!complete || interrupted) {
        if (!o.silent) std::fprintf(stderr, "caustica: interrupted; %s not written\n", path.c_str());
        return exit_interrupted;
    }
    const RenderStats stats = session.stats();
    try {
        write_image_atomic(path, session.image(), write_settings(o), render_metadata(job, scene_path, stats), &interrupted);
    } catch (const ImageWriteCancelled&) {
        if (!o.silent) std::fprintf(stderr, "caustica: interrupted; %s not written\n", path.c_str());
        return exit_interrupted;
    }
    print_stats(stats, o.timing, o.stats);
    if (!o.silent)
        std::printf("wrote %s (%d x %d, %.2f s)\n", path.c_str(), session.image().width, session.image().height,
                    stats.total_seconds);
    return exit_ok;
}

}  // namespace

std::string render_help() {
    return "usage: caustica render [options] SCENE.lua [-o OUT.png|OUT.exr|OUT.pfm]\n"
           "\n"
           "Runs the scene script and renders every gr.render it calls. Without -o each render\n"
           "writes the file the script names, relative to the current folder; with -o a single\n"
           "render writes OUT.png and several write OUT-1.png, OUT-2.png, ...\n"
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

int run_render_command(const std::vector<std::string>& args) {
    RenderArguments parsed = parse_arguments(args);
    if (parsed.help) {
        std::printf("%s", render_help().c_str());
        return exit_ok;
    }
    Options command_line;
    apply_option_tokens(command_line, parsed.option_tokens);
    if (!std::filesystem::is_regular_file(parsed.scene))
        throw InputError(parsed.scene + ": no such scene file");

    std::signal(SIGINT, on_interrupt);
    std::signal(SIGTERM, on_interrupt);
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
        std::fprintf(stderr, "caustica: interrupted while running %s\n", parsed.scene.c_str());
        return exit_interrupted;
    } catch (const std::bad_alloc&) {
        throw InputError(parsed.scene + ": not enough memory to run the script");
    }
    if (!command_line.silent)
        for (const std::string& w : script.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (script.renders.empty()) throw InputError(parsed.scene + ": the script calls no gr.render; nothing to render");

    // The command line wins over gr.option: re-apply its tokens on top of each job's options.
    std::vector<RenderJob> jobs = script.renders;
    std::vector<std::string> paths;
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        jobs[i].apply_command_line(parsed.option_tokens);
        paths.push_back(output_path(parsed, jobs[i], i, jobs.size()));
        check_writable(paths.back(), jobs[i], !parsed.output.empty());
    }
    for (const RenderJob& job : jobs) {
        const Options& o = job.options;
        if (o.integrator == IntegratorKind::progressive && o.passes == 0 && o.time_limit <= 0.0 && o.target_error <= 0.0)
            throw InputError("--passes 0 renders until another rule stops it: give --time or --target-error too");
    }
    RenderSession session;
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        int code = exit_ok;
        try {
            code = render_job(session, jobs[i], parsed.scene, paths[i]);
        } catch (const std::bad_alloc&) {
            // The scene asks for more than the machine can hold: a scene error (exit 2, README).
            throw InputError(jobs[i].where, "gr.render: not enough memory to render '" + paths[i] + "' (" +
                                                job_size(jobs[i]) + " pixels); lower the resolution or the photon count");
        }
        if (code != exit_ok) return code;
    }
    return exit_ok;
}

}  // namespace caustica
