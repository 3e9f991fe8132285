#include "app/compare_command.h"

#include "app/render_command.h"
#include "core/io/image_io.h"
#include "core/render/image_error.h"
#include "core/scene/source_location.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace caustica {
namespace {

const char* compare_usage =
    "usage: caustica compare IMAGE REFERENCE\n"
    "\n"
    "The caustic error of IMAGE against REFERENCE (docs/ACCURACY.md), each a PNG (values / 255, as\n"
    "caustica writes them), an OpenEXR or a PFM of the same size, on the values a PNG shows (each\n"
    "channel clamped to [0, 1]): the relative RMSE over the reference's caustic region (pixels whose\n"
    "value reaches 10% of the 99th percentile of its non-zero values), the relative bias there, and\n"
    "the RMSE over the whole image. To measure a progressive render as the renderer's own estimate\n"
    "does, render both caustics only:\n"
    "  caustica render --integrator progressive --draw-caustics-only --disable-aa SCENE.lua -o X.pfm\n";

/// Refuses an image with a NaN or infinite value, naming the file and the first such pixel: its
/// error would print as nan.
void check_finite(const Image& image, const std::string& path) {
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
        const glm::vec3& p = image.pixels[i];
        if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) continue;
        const std::size_t width = static_cast<std::size_t>(image.width);
        throw InputError(path + ": pixel (" + std::to_string(i % width) + ", " + std::to_string(i / width) +
                         ") is not a finite number");
    }
}

}  // namespace

int run_compare_command(const std::vector<std::string>& args) {
    for (const std::string& a : args)
        if (a == "-h" || a == "--help") {
            std::printf("%s", compare_usage);
            return exit_ok;
        }
    if (args.size() != 2) throw InputError(std::string("compare takes an image and a reference\n\n") + compare_usage);
    const Image image = read_image_file(args[0]);
    const Image reference = read_image_file(args[1]);
    check_finite(image, args[0]);
    check_finite(reference, args[1]);
    if (image.width != reference.width || image.height != reference.height)
        throw InputError(args[0] + " is " + std::to_string(image.width) + " x " + std::to_string(image.height) + ", " +
                         args[1] + " is " + std::to_string(reference.width) + " x " +
                         std::to_string(reference.height) + ": compare needs images of one size");
    const std::vector<std::size_t> region = caustic_region(reference);
    if (region.empty()) throw InputError(args[1] + ": every pixel is black, so there is no caustic region to compare over");
    const ImageError e = compare_images(image, reference, region);
    std::printf("caustic region       %zu pixels of %zu\n", e.region_pixels, reference.pixels.size());
    std::printf("relative RMSE        %.4f   (over the caustic region: the caustic error)\n", e.rel_rmse);
    std::printf("relative bias        %+.4f  (the image's sum over the region against the reference's)\n", e.rel_bias);
    std::printf("RMSE                 %.4f   (every pixel and channel)\n", e.rmse);
    return exit_ok;
}

}  // namespace caustica
