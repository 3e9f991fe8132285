#include "ui/save_image.h"

#include "core/integrators/registry.h"

#include "ui/preview_driver.h"

#include "core/io/image_io.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace caustica::ui {
namespace {

std::string format_vector(const glm::dvec3& v) {
    char text[96];
    std::snprintf(text, sizeof text, "%.9g %.9g %.9g", v.x, v.y, v.z);
    return text;
}

std::string format_number(const char* format, double value) {
    char text[64];
    std::snprintf(text, sizeof text, format, value);
    return text;
}

/// Which passes the saved samples come from: for an accumulation, how many passes it averaged.
std::string passes_done(const SessionProgress& p) {
    if (p.accumulating) return std::to_string(p.passes_done);
    if (p.finished) return "complete";
    if (p.showing_direct_light) return "direct light only (" + p.stage + " under way)";
    const std::size_t per_pass = p.passes > 0 ? p.tiles_total / static_cast<std::size_t>(p.passes) : 0;
    const std::size_t whole = per_pass > 0 ? p.tiles_done / per_pass : 0;
    return std::to_string(whole) + " of " + std::to_string(p.passes) + " passes (" + p.stage + " under way)";
}

/// The refusal of a script's output name that leads outside the current folder.
SaveResult refused_outside(const RenderJob& job, const std::string& reason) {
    return {SaveOutcome::failed, InputError(job.where, "gr.render: output " + reason +
                                                           " (a scene's name saves below the current folder; type "
                                                           "another name to save elsewhere)").what()};
}

}  // namespace

Options rendered_options(const RenderJob& job, const SessionProgress& progress) {
    Options options = job.options;
    // An accumulation saved before its end holds the passes done so far, whatever rules were to
    // end it (refining until paused has none `render` accepts): those passes are what it rendered.
    if (progress.accumulating && !progress.finished) {
        options.passes = std::max(1, progress.passes_done);
        options.passes_given = true;
        options.time_limit = 0.0;
        options.target_error = 0.0;
    }
    return options;
}

std::vector<std::pair<std::string, std::string>> preview_metadata(const RenderJob& job, const std::string& scene_path,
                                                                  const SessionProgress& progress) {
    const CameraDesc& c = job.camera;
    char fovy[32];
    std::snprintf(fovy, sizeof fovy, "%.9g", c.fovy_degrees);
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.3f", progress.elapsed_seconds);
    std::vector<std::pair<std::string, std::string>> text = {
        {"Software", "caustica " CAUSTICA_VERSION " (view)"},
        {"Source", scene_path},
        {"caustica:integrator", integrator_entry(job.options.integrator).name},
        {"caustica:options", describe_non_default(rendered_options(job, progress))},
        {"caustica:camera", "eye " + format_vector(c.eye) + " view " + format_vector(c.view) + " up " +
                                format_vector(c.up) + " fovy " + fovy},
        {"caustica:size", std::to_string(job.width) + "x" + std::to_string(job.height)},
        {"caustica:passes", passes_done(progress)},
        {"caustica:render-seconds", seconds}};
    if (!progress.accumulating) return text;
    // A progressive accumulation: what the saved mean is made of, and how good it is thought to be.
    const ErrorEstimate& e = progress.error;
    text.push_back({"caustica:pass-limit", progress.pass_limit > 0 ? std::to_string(progress.pass_limit) : "none"});
    text.push_back({"caustica:samples-per-pixel", format_number("%.6g", progress.samples_per_pixel)});
    text.push_back({"caustica:photons-emitted", std::to_string(progress.photons_emitted)});
    text.push_back({"caustica:radius", format_number("%.6g", progress.radius)});
    text.push_back({"caustica:estimated-error",
                    e.known ? format_number("%.4g", e.relative) + " (noise " + format_number("%.4g", e.noise) +
                                  ", bias " + format_number("%.4g", e.bias) + ")"
                            : "unknown (fewer than 2 passes)"});
    const char* state = progress.running ? "refining" : progress.finished ? "stopped" : "paused";
    text.push_back({"caustica:state", progress.finished ? std::string(state) + " by " + stop_reason(progress.stopped_by) : state});
    return text;
}

SaveResult save_preview_image(const std::string& path, const Image& image, const RenderJob& job,
                              const std::string& scene_path, const SessionProgress& progress, bool overwrite,
                              std::optional<SaveToneSettings> tone, OutputPlace place) {
    namespace fs = std::filesystem;
    if (image.width <= 0 || image.height <= 0) return {SaveOutcome::failed, "nothing rendered yet"};
    const std::optional<ImageFormat> format = image_format_of(path);
    if (!format) return {SaveOutcome::failed, path + ": the file name must end in .png, .exr or .pfm"};
    std::error_code ec;
    const fs::path absolute = fs::absolute(path, ec);
    const std::string shown = ec ? path : absolute.lexically_normal().string();
    if (place == OutputPlace::inside_current_folder)  // before asking whether to replace a file out there
        if (const std::string outside = output_outside_current_folder(path); !outside.empty())
            return refused_outside(job, outside);
    if (!overwrite && fs::exists(path, ec)) return {SaveOutcome::exists, shown + " exists"};
    ImageWriteSettings settings;
    settings.encoding = job.options.srgb ? PixelEncoding::srgb : PixelEncoding::clamped_linear;
    settings.tonemap = tone ? tone->tonemap : job.options.tonemap;
    settings.exposure_stops = tone ? tone->exposure_stops : static_cast<float>(job.options.exposure);
    settings.exr_pixel = job.options.exr_pixel;
    ImageMetadata metadata = preview_metadata(job, scene_path, progress);
    if (*format == ImageFormat::png && (settings.tonemap != Tonemap::clamp || settings.exposure_stops != 0.0f))
        metadata.push_back({"caustica:tonemap", std::string(tonemap_name(settings.tonemap)) + ", exposure " +
                                                    format_number("%.6g", settings.exposure_stops) + " stops"});
    else if (settings.exposure_stops != 0.0f)
        metadata.push_back({"caustica:exposure", format_number("%.6g", settings.exposure_stops) + " stops"});
    try {
        // A script's name is written as named, as `caustica render` writes it.
        const bool as_named = ec || place == OutputPlace::inside_current_folder;
        write_image_atomic(as_named ? path : absolute.string(), image, settings, metadata, nullptr, place);
    } catch (const OutputOutsideFolder& e) {
        return refused_outside(job, e.what());
    } catch (const std::exception& e) {
        return {SaveOutcome::failed, e.what()};
    }
    const std::string passes = progress.accumulating ? passes_done(progress) + " passes" : passes_done(progress);
    return {SaveOutcome::written, "wrote " + shown + " (" + std::to_string(image.width) + " x " +
                                      std::to_string(image.height) + ", " + passes + ")"};
}

SaveResult save_preview_png(const std::string& path, const Image& image, const RenderJob& job,
                            const std::string& scene_path, const SessionProgress& progress, bool overwrite) {
    if (image_format_of(path) != ImageFormat::png)
        return {SaveOutcome::failed, path + ": the file name must end in .png"};
    return save_preview_image(path, image, job, scene_path, progress, overwrite);
}

}  // namespace caustica::ui
