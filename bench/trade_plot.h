// Log-log line plots for bench/trade, drawn by gnuplot (Debian's gnuplot-nox) when it is on PATH.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace caustica::trade {

/// One curve of a panel: points (x, y) in order, drawn with points and lines, or a plain dashed line.
struct Curve {
    std::string title;
    std::vector<std::pair<double, double>> points;
    int colour = 0;          ///< index into a fixed palette, so one value keeps one colour across panels
    bool dashed_line = false;  ///< a fitted line: dashed, no point markers
};

/// One log-log panel.
struct Panel {
    std::string title, x_label, y_label;
    std::vector<Curve> curves;
};

/// A PNG of `rows` x `columns` panels.
struct Figure {
    std::string png_path;
    std::string title;
    int rows = 1, columns = 1;
    int width = 1200, height = 800;  ///< pixels
    std::vector<Panel> panels;
};

/// True when a `gnuplot` executable is on PATH.
bool gnuplot_available();

/// Writes PNG_PATH.gp and PNG_PATH.dat beside the figure and runs gnuplot on them.
/// Returns "" on success, or what went wrong.
std::string plot_figure(const Figure& figure);

}  // namespace caustica::trade
