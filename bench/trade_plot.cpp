#include "bench/trade_plot.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace caustica::trade {
namespace {

/// Colour-blind-safe palette (Okabe-Ito), then a few extras.
constexpr const char* palette[] = {"#0072B2", "#E69F00", "#009E73", "#D55E00", "#CC79A7",
                                   "#56B4E9", "#000000", "#F0E442", "#999999"};
constexpr int palette_size = sizeof(palette) / sizeof(palette[0]);

/// Quotes a string for gnuplot (single quotes; a quote is doubled).
std::string quoted(const std::string& text) {
    std::string out = "'";
    for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
    return out + "'";
}

/// Quotes a string for the shell: single quotes, each quote closed, escaped and reopened.
std::string shell_quoted(const std::string& text) {
    std::string out = "'";
    for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

}  // namespace

bool gnuplot_available() {
    const char* path = std::getenv("PATH");
    if (!path) return false;
    std::stringstream dirs(path);
    std::string dir;
    while (std::getline(dirs, dir, ':'))
        if (!dir.empty() && std::filesystem::exists(std::filesystem::path(dir) / "gnuplot")) return true;
    return false;
}

std::string plot_figure(const Figure& figure) {
    const std::string script_path = figure.png_path + ".gp", data_path = figure.png_path + ".dat";
    std::ofstream data(data_path);
    std::ofstream script(script_path);
    script << "# Made by bench/trade: gnuplot " << script_path << "\n"
           << "set terminal pngcairo size " << figure.width << "," << figure.height << " noenhanced font 'sans,11'\n"
           << "set output " << quoted(figure.png_path) << "\n"
           << "set logscale xy\nset format x '%g'\nset format y '%g'\n"
           << "set grid xtics ytics mxtics mytics lc rgb '#dddddd'\n"
           << "set key bottom left spacing 1.1 box opaque\n"
           << "set multiplot layout " << figure.rows << "," << figure.columns << " title "
           << quoted(figure.title) << " font 'sans,14'\n";
    int block = 0;
    for (const Panel& panel : figure.panels) {
        script << "set title " << quoted(panel.title) << "\nset xlabel " << quoted(panel.x_label)
               << "\nset ylabel " << quoted(panel.y_label) << "\n";
        std::string plots;
        for (const Curve& curve : panel.curves) {
            if (curve.points.empty()) continue;
            for (const auto& [x, y] : curve.points) data << x << ' ' << y << '\n';
            data << "\n\n";
            if (!plots.empty()) plots += ", \\\n     ";
            plots += quoted(data_path) + " index " + std::to_string(block++) + " using 1:2 with " +
                     (curve.dashed_line ? "lines dt 2 lw 1.5" : "linespoints lw 2 pt 7 ps 0.7") + " lc rgb '" +
                     palette[curve.colour % palette_size] + "' title " + quoted(curve.title);
        }
        if (plots.empty()) script << "set multiplot next\n";
        else script << "plot " << plots << "\n";
    }
    script << "unset multiplot\n";
    data.close();
    script.close();
    if (!data || !script) return "cannot write " + script_path + " or " + data_path;
    const std::string command = "gnuplot " + shell_quoted(script_path) + " 2>" + shell_quoted(figure.png_path + ".log");
    if (std::system(command.c_str()) != 0) return "gnuplot failed on " + script_path + " (see " + figure.png_path + ".log)";
    std::filesystem::remove(figure.png_path + ".log");
    return {};
}

}  // namespace caustica::trade
