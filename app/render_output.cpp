// Writing a frame of `caustica render`: the image file with its metadata, then the report (-t, -S
// and the "wrote" line).
#include "app/render_output.h"

#include "core/integrators/registry.h"

#include "app/render_command.h"
#include "app/render_interrupt.h"
#include "app/render_plan.h"
#include "core/io/image_io.h"
#include "core/util/printable_text.h"

#include <algorithm>
#include <cstdarg>
#include <cstdio>

namespace caustica {
namespace {

/// printf into a string.
[[gnu::format(printf, 2, 3)]] void appendf(std::string& out, const char* format, ...) {
    char line[512];
    va_list args;
    va_start(args, format);
    const int n = std::vsnprintf(line, sizeof line, format, args);
    va_end(args);
    if (n > 0) out.append(line, static_cast<std::size_t>(std::min<int>(n, sizeof line - 1)));
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

}  // namespace

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
        appendf(out, "  scene memory           %9.1f MiB estimated (meshes and their BVH, instances, textures)\n",
                     stats.scene.estimated_bytes / 1048576.0);
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

int write_frame(const AnimationFrame& frame, const std::string& scene_path, const std::string& label, const Image& image,
                const RenderStats& stats, const std::string* stats_from_rank, const std::vector<LayerImage>* layers) {
    const RenderJob& job = frame.job;
    const std::string& path = frame.path;
    const Options& o = job.options;
    const OutputPlace place = frame.named_by_script ? OutputPlace::inside_current_folder : OutputPlace::anywhere;
    try {
        const ImageMetadata metadata = render_metadata(job, scene_path, stats, label);
        if (o.layers) {
            // render_plan refused what cannot hold layers; an empty list here is a render that made none.
            if (!layers || layers->empty()) throw std::logic_error("--layers: no layers were rendered for " + path);
            std::vector<Image> scaled;
            const std::vector<ExrChannel> channels =
                layer_channels(image, *layers, static_cast<float>(o.exposure), scaled);
            write_exr_channels_atomic(path, image.width, image.height, channels, o.exr_pixel, metadata, &interrupted,
                                      place);
        } else {
            write_image_atomic(path, image, write_settings(o), metadata, &interrupted, place);
        }
    } catch (const ImageWriteCancelled&) {
        if (!o.silent) std::fprintf(stderr, "caustica: interrupted; %s not written\n", printable_text(path).c_str());
        return exit_interrupted;
    } catch (const OutputOutsideFolder& e) {
        throw output_outside(job, e.what());
    }
    if (stats_from_rank)
        std::fputs(stats_from_rank->c_str(), stderr);
    else
        print_stats(stats, o.timing, o.stats);
    if (!o.silent)
        std::printf("wrote %s (%d x %d, %.2f s)\n", printable_text(path).c_str(), image.width, image.height,
                    stats.total_seconds);
    return exit_ok;
}

}  // namespace caustica
