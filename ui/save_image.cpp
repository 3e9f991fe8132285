#include "ui/save_image.h"

#include "core/io/png_io.h"

#include <cstdio>
#include <filesystem>

namespace caustica::ui {
namespace {

std::string format_vector(const glm::dvec3& v) {
    char text[96];
    std::snprintf(text, sizeof text, "%.9g %.9g %.9g", v.x, v.y, v.z);
    return text;
}

/// Which passes the saved samples come from.
std::string passes_done(const SessionProgress& p) {
    if (p.finished) return "complete";
    const std::size_t per_pass = p.passes > 0 ? p.tiles_total / static_cast<std::size_t>(p.passes) : 0;
    const std::size_t whole = per_pass > 0 ? p.tiles_done / per_pass : 0;
    return std::to_string(whole) + " of " + std::to_string(p.passes) + " passes (" + p.stage + " under way)";
}

}  // namespace

std::vector<std::pair<std::string, std::string>> preview_metadata(const RenderJob& job, const std::string& scene_path,
                                                                  const SessionProgress& progress) {
    const CameraDesc& c = job.camera;
    char fovy[32];
    std::snprintf(fovy, sizeof fovy, "%.9g", c.fovy_degrees);
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%.3f", progress.elapsed_seconds);
    return {{"Software", "caustica " CAUSTICA_VERSION " (view)"},
            {"Source", scene_path},
            {"caustica:options", describe_non_default(job.options)},
            {"caustica:camera", "eye " + format_vector(c.eye) + " view " + format_vector(c.view) + " up " +
                                    format_vector(c.up) + " fovy " + fovy},
            {"caustica:size", std::to_string(job.width) + "x" + std::to_string(job.height)},
            {"caustica:passes", passes_done(progress)},
            {"caustica:render-seconds", seconds}};
}

SaveResult save_preview_png(const std::string& path, const Image& image, const RenderJob& job,
                            const std::string& scene_path, const SessionProgress& progress, bool overwrite) {
    namespace fs = std::filesystem;
    if (image.width <= 0 || image.height <= 0) return {SaveOutcome::failed, "nothing rendered yet"};
    if (fs::path(path).extension() != ".png") return {SaveOutcome::failed, path + ": the file name must end in .png"};
    std::error_code ec;
    if (!overwrite && fs::exists(path, ec)) return {SaveOutcome::exists, path + " exists"};
    try {
        write_png_atomic(path, image, job.options.srgb ? PixelEncoding::srgb : PixelEncoding::clamped_linear,
                         preview_metadata(job, scene_path, progress));
    } catch (const std::exception& e) {
        return {SaveOutcome::failed, e.what()};
    }
    return {SaveOutcome::written, "wrote " + path + " (" + std::to_string(image.width) + " x " +
                                      std::to_string(image.height) + ", " + passes_done(progress) + ")"};
}

}  // namespace caustica::ui
