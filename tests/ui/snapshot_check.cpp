// Checks a `caustica view --snapshot` PNG of the default 1280 x 720 window: written by the
// expected platform, the sidebar panel on the right, a rendered (not blank) image on the left,
// and the projection-map overlay's outline on it; with --cells also its occupied cells (turned on
// by a key tap, xvfb_view_test.sh). Used by xvfb_view_test.sh.
#include "core/io/png_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

int failures = 0;

void check(bool ok, const char* what) {
    std::printf("%s: %s\n", ok ? "ok  " : "FAIL", what);
    failures += !ok;
}

}  // namespace

int main(int argc, char** argv) {
    const bool cells_expected = argc == 4 && std::string(argv[3]) == "--cells";
    if (argc != 3 && !cells_expected) {
        std::fprintf(stderr, "usage: snapshot_check SNAPSHOT.png PLATFORM [--cells]\n");
        return 2;
    }
    const caustica::Png8 png = caustica::read_png(argv[1]);
    auto at = [&](int x, int y, int c) { return static_cast<int>(png.data[(static_cast<std::size_t>(y) * png.width + x) * png.channels + c]); };
    check(png.width == 1280 && png.height == 720, "the window is 1280 x 720");
    std::string platform;
    for (const auto& [key, value] : png.text)
        if (key == "caustica:platform") platform = value;
    check(platform == argv[2], ("drawn by " + std::string(argv[2])).c_str());
    if (png.width != 1280 || png.height != 720) return 1;

    // The sidebar (right 370 pixels): mostly ImGui's dark window background (about 16, 16, 16).
    long dark = 0, total = 0;
    for (int y = 30; y < 720; ++y)
        for (int x = 914; x < 1268; ++x, ++total)
            dark += std::abs(at(x, y, 0) - 16) <= 3 && std::abs(at(x, y, 1) - 16) <= 3 && std::abs(at(x, y, 2) - 16) <= 3;
    check(dark > total * 4 / 10, "the sidebar panel is on the right");

    // The image area: a render with some contrast, not one flat colour.
    double sum = 0.0, sum2 = 0.0;
    long count = 0, yellow = 0, orange = 0;
    for (int y = 40; y < 700; ++y)
        for (int x = 20; x < 890; ++x, ++count) {
            const double v = (at(x, y, 0) + at(x, y, 1) + at(x, y, 2)) / 3.0;
            sum += v;
            sum2 += v * v;
            yellow += at(x, y, 0) > 220 && at(x, y, 1) > 180 && at(x, y, 2) < 60;
            // OverlayStyle::cell_colour (1, 0.35, 0.1) at 70 % over the image
            orange += at(x, y, 0) > 190 && at(x, y, 1) > 70 && at(x, y, 1) < 160 && at(x, y, 2) < 110 &&
                      at(x, y, 0) - at(x, y, 1) > 70;
        }
    const double mean = sum / count, deviation = std::sqrt(std::max(0.0, sum2 / count - mean * mean));
    std::printf("      image area: mean %.1f, standard deviation %.1f, %ld outline pixels, %ld cell pixels\n", mean,
                deviation, yellow, orange);
    check(deviation > 10.0, "the image area shows a render");
    check(yellow > 200, "the projection-map outline is drawn");
    if (cells_expected) check(orange > 200, "the occupied cells are drawn (C, tapped)");
    return failures == 0 ? 0 : 1;
}
