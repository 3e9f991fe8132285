// Composes PNGs into one for the peer benchmark's documentation (docs/PEERS.md): the inputs side by
// side (or stacked with --vertical), separated by a white gap, each optionally cropped to the same
// rectangle and enlarged by an integer factor (nearest neighbour, so pixels and noise stay
// visible).
//
//   side_by_side OUT.png IN.png... [--crop X0 Y0 X1 Y1] [--zoom Z] [--gap N] [--vertical]
//
// Inputs of different sizes are top/left aligned on a white background. Exit status 2 on errors.
#include "core/render/image.h"
#include "core/io/png_io.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

using namespace caustica;

namespace {

/// Linear pixel values of an 8-bit PNG cropped to [x0, x1) x [y0, y1) and enlarged `zoom` times.
Image crop_and_zoom(const Png8& png, int x0, int y0, int x1, int y1, int zoom) {
    Image out((x1 - x0) * zoom, (y1 - y0) * zoom);
    for (int y = 0; y < out.height; ++y) {
        for (int x = 0; x < out.width; ++x) {
            const int sx = x0 + x / zoom, sy = y0 + y / zoom;
            const std::size_t base = (static_cast<std::size_t>(sy) * png.width + sx) * png.channels;
            for (int c = 0; c < 3; ++c) out.at(x, y)[c] = png.data[base + (png.channels >= 3 ? c : 0)] / 255.0f;
        }
    }
    return out;
}

int usage(const std::string& message) {
    std::fprintf(stderr,
                 "side_by_side: %s\nusage: side_by_side OUT.png IN.png... [--crop X0 Y0 X1 Y1] [--zoom Z] [--gap N] "
                 "[--vertical]\n",
                 message.c_str());
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> paths;
    int crop[4] = {0, 0, 0, 0};
    bool has_crop = false, vertical = false;
    int zoom = 1, gap = 8;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--crop") {
            if (i + 4 >= argc) return usage("--crop needs X0 Y0 X1 Y1");
            for (int k = 0; k < 4; ++k) crop[k] = std::atoi(argv[i + 1 + k]);
            has_crop = true;
            i += 4;
        } else if (arg == "--zoom" || arg == "--gap") {
            if (i + 1 >= argc) return usage(arg + " needs a number");
            (arg == "--zoom" ? zoom : gap) = std::atoi(argv[++i]);
        } else if (arg == "--vertical") {
            vertical = true;
        } else if (!arg.empty() && arg[0] == '-') {
            return usage("unknown option " + arg);
        } else {
            paths.push_back(arg);
        }
    }
    if (paths.size() < 2) return usage("an output and at least one input are needed");
    if (zoom < 1 || zoom > 16 || gap < 0) return usage("zoom must be 1..16 and the gap not negative");

    std::vector<Image> panels;
    try {
        for (std::size_t i = 1; i < paths.size(); ++i) {
            const Png8 png = read_png(paths[i]);
            int x0 = 0, y0 = 0, x1 = png.width, y1 = png.height;
            if (has_crop) {
                x0 = crop[0], y0 = crop[1], x1 = crop[2], y1 = crop[3];
                if (x0 < 0 || y0 < 0 || x1 > png.width || y1 > png.height || x0 >= x1 || y0 >= y1)
                    return usage("the crop is empty or outside " + paths[i]);
            }
            panels.push_back(crop_and_zoom(png, x0, y0, x1, y1, zoom));
        }
    } catch (const std::exception& e) {
        return usage(e.what());
    }

    int width = 0, height = 0;
    for (const Image& p : panels) {
        width = vertical ? std::max(width, p.width) : width + p.width;
        height = vertical ? height + p.height : std::max(height, p.height);
    }
    const int gaps = gap * static_cast<int>(panels.size() - 1);
    (vertical ? height : width) += gaps;
    Image out(width, height);
    std::fill(out.pixels.begin(), out.pixels.end(), glm::vec3(1.0f));
    int offset = 0;
    for (const Image& p : panels) {
        for (int y = 0; y < p.height; ++y)
            for (int x = 0; x < p.width; ++x) out.at(vertical ? x : offset + x, vertical ? offset + y : y) = p.at(x, y);
        offset += (vertical ? p.height : p.width) + gap;
    }
    try {
        write_png_atomic(paths[0], out, PixelEncoding::clamped_linear);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "side_by_side: %s\n", e.what());
        return 2;
    }
    return 0;
}
