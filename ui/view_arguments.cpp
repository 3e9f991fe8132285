#include "ui/view_arguments.h"

#include "core/scene/options.h"
#include "core/scene/source_location.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <unistd.h>

namespace caustica::ui {
namespace {

int parse_int(const std::string& flag, const std::string& text, int lo, int hi) {
    int value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size() || value < lo || value > hi)
        throw InputError(flag + " " + text + ": expects a whole number from " + std::to_string(lo) + " to " +
                         std::to_string(hi));
    return value;
}

double parse_double(const std::string& flag, const std::string& text) {
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
        throw InputError(flag + " " + text + ": expects a finite number");
    return value;
}

/// Splits "A<sep>B" into two parts, or throws.
std::pair<std::string, std::string> split_pair(const std::string& flag, const std::string& text, char sep,
                                               const char* form) {
    const auto at = text.find(sep);
    if (at == std::string::npos || at == 0 || at + 1 == text.size())
        throw InputError(flag + " " + text + ": expects " + form);
    return {text.substr(0, at), text.substr(at + 1)};
}

}  // namespace

ViewArguments parse_view_arguments(const std::vector<std::string>& args) {
    ViewArguments parsed;
    std::vector<std::string> tokens;
    auto value_of = [&](std::size_t& i, const std::string& flag) -> std::string {
        const std::string& a = args[i];
        if (a.size() > flag.size() && a[flag.size()] == '=') return a.substr(flag.size() + 1);
        if (i + 1 >= args.size()) throw InputError(flag + ": expects a value");
        return args[++i];
    };
    auto is = [](const std::string& a, const std::string& flag) {
        return a == flag || (a.size() > flag.size() && a.compare(0, flag.size() + 1, flag + "=") == 0);
    };
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-h" || a == "--help") {
            parsed.help = true;
        } else if (is(a, "--frames")) {
            parsed.frames = parse_int("--frames", value_of(i, "--frames"), 1, 1000000);
        } else if (is(a, "--snapshot")) {
            parsed.snapshot = value_of(i, "--snapshot");
            if (std::filesystem::path(parsed.snapshot).extension() != ".png")
                throw InputError("--snapshot " + parsed.snapshot + ": the file must end in .png");
        } else if (a == "--overlay") {
            parsed.overlay = true;
        } else if (is(a, "--orbit")) {
            const std::string v = value_of(i, "--orbit");
            const auto [yaw, pitch] = split_pair("--orbit", v, ',', "YAW,PITCH in degrees, e.g. 30,-10");
            parsed.orbit = glm::dvec2(parse_double("--orbit", yaw), parse_double("--orbit", pitch));
        } else if (is(a, "--allow-read")) {
            parsed.allow_read.push_back(value_of(i, "--allow-read"));
        } else if (a == "--headless") {
            parsed.headless = true;
        } else if (a == "--final") {
            parsed.final_image = true;
        } else if (a == "--after-key") {
            parsed.after_key = true;
        } else if (is(a, "--size")) {
            const std::string v = value_of(i, "--size");
            const auto [w, h] = split_pair("--size", v, 'x', "WIDTHxHEIGHT, e.g. 1280x720");
            parsed.width = parse_int("--size", w, 320, 8192);
            parsed.height = parse_int("--size", h, 240, 8192);
        } else {
            tokens.push_back(a);
        }
    }
    if (parsed.help) return parsed;
    std::vector<std::string> positional;
    Options check;
    apply_option_tokens(check, tokens, &positional);  // every render option is checked before a window opens
    if (positional.size() > 1)
        throw InputError("one scene at a time, got '" + positional[0] + "' and '" + positional[1] + "'");
    if (!positional.empty()) parsed.scene = positional[0];
    for (const std::string& t : tokens)
        if (t != parsed.scene) parsed.option_tokens.push_back(t);
    return parsed;
}

std::string snapshot_target_problem(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path target(path);
    if (fs::is_directory(target, ec)) return path + ": is a folder, not a file";
    const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    if (!fs::exists(folder, ec)) return path + ": the folder " + folder.string() + " does not exist";
    if (!fs::is_directory(folder, ec)) return path + ": " + folder.string() + " is not a folder";
    if (::access(folder.c_str(), W_OK) != 0) return path + ": the folder " + folder.string() + " is not writable";
    return {};
}

int scripted_exit_code(bool has_scene, const std::string& error, bool timed_out) {
    if (timed_out) return 1;
    return has_scene && error.empty() ? 0 : 2;
}

std::string view_help() {
    return "usage: caustica view [SCENE.lua] [--frames N] [--snapshot FILE.png] [--overlay] [--orbit YAW,PITCH]\n"
           "                     [--headless] [--final] [--size WxH] [--after-key] [render options]\n"
           "\n"
           "Opens an interactive preview: the ray tracer refines the image in the background while you\n"
           "orbit the camera and tune the caustics. Press F1 in the window for the keys.\n"
           "\n"
           "  --frames N         run N frames (and at least until the first full-resolution pass), then exit\n"
           "  --snapshot FILE    write the whole window, panels included, to FILE.png before exiting\n"
           "  --overlay          start with the projection-map overlay on\n"
           "  --orbit YAW,PITCH  orbit the camera by these degrees before rendering (+yaw: to the camera's\n"
           "                     right around the target, +pitch: upwards)\n"
           "  --headless         render the window off-screen with OSMesa (chosen automatically without DISPLAY)\n"
           "  --final            with --snapshot: wait until every pass (anti-aliasing too) is done; the\n"
           "                     progressive integrator refines without end unless --passes, --time or\n"
           "                     --target-error says when to stop (else --final waits for its first pass)\n"
           "  --size WxH         window size (default 1280x720)\n"
           "  --after-key        with --frames/--snapshot: count the frames only from the first key pressed\n"
           "                     in the window (for tests that send keys, e.g. with xdotool)\n"
           "  --allow-read DIR   let scenes read files under DIR too (repeatable; a shared texture folder)\n"
           "Render options ('caustica render --help') apply over the scene's gr.option calls, for\n"
           "SCENE.lua only: scenes opened later start from their own gr.option calls. The preview\n"
           "renders what 'caustica render SCENE.lua [options]' renders; its sidebar lists what you\n"
           "change and copies the equivalent command line.\n";
}

}  // namespace caustica::ui
