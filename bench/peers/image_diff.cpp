// Caustic quality for the peer benchmark (docs/PEERS.md): the RMSE between a render and a reference
// over a rectangle and/or a mask, in values clamped to [0, 1] (what a PNG shows) over all three
// channels. The images are PNG (8-bit values / 255), EXR or PFM (linear floats, clamped): an 8-bit
// image is quantised in steps of 1/255: on a dim caustic (a mean of 0.07) a PNG is 0.03 from its
// own float image (truncation) and two PNGs differ by up to 0.02 from the steps alone, so lower
// errors need float images. A non-finite value in a float image is refused.
//
//   image_diff TEST REFERENCE [--rect X0 Y0 X1 Y1] [--mask MASK.png | --mask-dark MASK.png]
//
// The rectangle is in pixels, X1 and Y1 exclusive; --mask selects the pixels where any of the
// mask's channels is non-zero, --mask-dark those where all are zero (e.g. the shadow of a glass
// object in a render without caustics and without ambient light: the region only the caustic
// lights); a rectangle and a mask together select their intersection; neither selects the whole
// image.
// Prints one line of key=value pairs:
//   rmse       root-mean-square difference
//   relative   rmse / mean of the reference over the region (an error independent of exposure)
//   mean_test, mean_ref   means over the region (do the two agree on the caustic's brightness?)
//   pixels     pixels in the region
//   clipped_ref  fraction of region pixels where the reference has a channel at 1 (255; the
//                error there is underestimated: clamping hides it)
// Exit status: 0 on success, 2 on a usage error, unreadable files, non-finite values or mismatched
// sizes.
#include "core/io/image_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

using caustica::Image;
using caustica::read_image_file;

namespace {

/// A pixel rectangle [x0, x1) x [y0, y1).
struct Rect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

/// Channel c of pixel (x, y) of an image read in any format, clamped to [0, 1] (a PNG's values / 255).
double shown(const Image& image, int x, int y, int c) {
    return std::clamp(static_cast<double>(image.at(x, y)[c]), 0.0, 1.0);
}

/// Whether the mask selects pixel (x, y): any of its channels is non-zero (a gray mask's value is
/// in all three).
bool selected(const Image& mask, int x, int y) {
    const glm::vec3& v = mask.at(x, y);
    return v.x > 0.0f || v.y > 0.0f || v.z > 0.0f;
}

int usage(const char* message) {
    std::fprintf(stderr, "image_diff: %s\nusage: image_diff TEST REFERENCE (PNG, EXR or PFM) [--rect X0 Y0 X1 Y1] "
                 "[--mask MASK.png | --mask-dark MASK.png]\n",
                 message);
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    std::string test_path, reference_path, mask_path;
    Rect rect;
    bool has_rect = false, dark_mask = false;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--rect") {
            if (i + 4 >= argc) return usage("--rect needs X0 Y0 X1 Y1");
            rect = {std::atoi(argv[i + 1]), std::atoi(argv[i + 2]), std::atoi(argv[i + 3]), std::atoi(argv[i + 4])};
            has_rect = true;
            i += 4;
        } else if (arg == "--mask" || arg == "--mask-dark") {
            if (i + 1 >= argc) return usage("--mask and --mask-dark need a PNG");
            if (!mask_path.empty()) return usage("one mask only");
            mask_path = argv[++i];
            dark_mask = arg == "--mask-dark";
        } else if (!arg.empty() && arg[0] == '-') {
            return usage(("unknown option " + arg).c_str());
        } else if (test_path.empty()) {
            test_path = arg;
        } else if (reference_path.empty()) {
            reference_path = arg;
        } else {
            return usage("too many files");
        }
    }
    if (reference_path.empty()) return usage("two images are needed");

    Image test, reference, mask;
    try {
        test = read_image_file(test_path);
        reference = read_image_file(reference_path);
        if (!mask_path.empty()) mask = read_image_file(mask_path);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "image_diff: %s\n", e.what());
        return 2;
    }
    for (const Image* image : {&test, &reference})
        for (const glm::vec3& p : image->pixels)
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                std::fprintf(stderr, "image_diff: %s has a non-finite value\n",
                             image == &test ? test_path.c_str() : reference_path.c_str());
                return 2;
            }
    if (test.width != reference.width || test.height != reference.height)
        return usage("the two images differ in size");
    if (!mask_path.empty() && (mask.width != reference.width || mask.height != reference.height))
        return usage("the mask differs in size from the images");
    if (!has_rect) rect = {0, 0, reference.width, reference.height};
    if (rect.x0 < 0 || rect.y0 < 0 || rect.x1 > reference.width || rect.y1 > reference.height ||
        rect.x0 >= rect.x1 || rect.y0 >= rect.y1)
        return usage("the rectangle is empty or outside the image");

    double squared = 0.0, sum_test = 0.0, sum_reference = 0.0;
    long long pixels = 0, clipped = 0;
    for (int y = rect.y0; y < rect.y1; ++y) {
        for (int x = rect.x0; x < rect.x1; ++x) {
            if (!mask_path.empty() && selected(mask, x, y) == dark_mask) continue;
            ++pixels;
            bool at_one = false;
            for (int c = 0; c < 3; ++c) {
                const double a = shown(test, x, y, c), b = shown(reference, x, y, c);
                squared += (a - b) * (a - b);
                sum_test += a;
                sum_reference += b;
                at_one = at_one || b >= 1.0;
            }
            clipped += at_one;
        }
    }
    if (pixels == 0) return usage("the region selects no pixels");
    const double values = 3.0 * static_cast<double>(pixels);
    const double rmse = std::sqrt(squared / values);
    const double mean_reference = sum_reference / values;
    std::printf("rmse=%.6f relative=%.6f mean_test=%.6f mean_ref=%.6f pixels=%lld clipped_ref=%.4f\n", rmse,
                mean_reference > 0.0 ? rmse / mean_reference : 0.0, sum_test / values, mean_reference, pixels,
                static_cast<double>(clipped) / static_cast<double>(pixels));
    return 0;
}
