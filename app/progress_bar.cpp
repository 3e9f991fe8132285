#include "app/progress_bar.h"

#include <algorithm>
#include <cstdio>
#include <unistd.h>

namespace caustica {

ProgressBar::ProgressBar(bool enabled) : active_(enabled && ::isatty(STDERR_FILENO)) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(double fraction, double elapsed, const std::string& stage) {
    if (!active_) return;
    fraction = std::clamp(fraction, 0.0, 1.0);
    constexpr int width = 30;
    const int filled = static_cast<int>(fraction * width + 0.5);
    char bar[width + 1];
    for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
    bar[width] = 0;
    char eta[32] = "";
    if (fraction > 0.02 && fraction < 1.0) std::snprintf(eta, sizeof eta, "  ETA %.1f s", elapsed * (1.0 / fraction - 1.0));
    std::fprintf(stderr, "\r[%s] %3d%%  %.1f s%s  %-24s", bar, static_cast<int>(fraction * 100.0), elapsed, eta,
                 stage.c_str());
    std::fflush(stderr);
    drawn_ = true;
}

void ProgressBar::finish() {
    if (!drawn_) return;
    std::fprintf(stderr, "\r%80s\r", "");
    std::fflush(stderr);
    drawn_ = false;
}

}  // namespace caustica
