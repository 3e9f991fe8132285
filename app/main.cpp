// caustica: the command-line entry point. Subcommands as in yocto's apps: render, view.
#include "app/render_command.h"
#include "app/view_command.h"
#include "core/scene/source_location.h"

#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

namespace {

const char* usage =
    "caustica " CAUSTICA_VERSION " - a ray tracer with photon-mapped caustics\n"
    "\n"
    "usage:\n"
    "  caustica render [options] SCENE.lua [-o OUT.png]   render every gr.render of a scene\n"
    "                                                     (-o OUT.exr or OUT.pfm: linear float)\n"
    "  caustica view [SCENE.lua] [--headless] [--snapshot FILE.png] ...\n"
    "                                                     interactive preview ('caustica view --help')\n"
    "  caustica SCENE.lua                                 same as 'caustica render SCENE.lua'\n"
    "  caustica --help | --version\n"
    "\n"
    "'caustica render --help' lists the options.\n";

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    try {
        if (args.empty()) {
            std::fprintf(stderr, "%s", usage);
            return caustica::exit_usage;
        }
        const std::string command = args[0];
        if (command == "-h" || command == "--help" || command == "help") {
            std::printf("%s", usage);
            return caustica::exit_ok;
        }
        if (command == "--version") {
            std::printf("caustica %s\n", CAUSTICA_VERSION);
            return caustica::exit_ok;
        }
        if (command == "render") return caustica::run_render_command({args.begin() + 1, args.end()});
        if (command == "view") return caustica::run_view_command({args.begin() + 1, args.end()});
        if (command.size() > 4 && command.compare(command.size() - 4, 4, ".lua") == 0)
            return caustica::run_render_command(args);
        std::fprintf(stderr, "caustica: unknown command '%s'\n\n%s", command.c_str(), usage);
        return caustica::exit_usage;
    } catch (const std::bad_alloc&) {
        // Only reached when no stage could name the cause: still a clear message, exit 2 (README).
        std::fprintf(stderr, "caustica: not enough memory for this scene (an allocation failed)\n");
        return caustica::exit_usage;
    } catch (const caustica::InputError& e) {
        std::fprintf(stderr, "caustica: %s\n", e.what());
        return caustica::exit_usage;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "caustica: %s\n", e.what());
        return caustica::exit_failure;
    }
}
