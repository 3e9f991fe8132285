// caustica: the command-line entry point. Subcommands as in yocto's apps: render, view.
#include "app/compare_command.h"
#include "app/render_command.h"
#include "app/view_command.h"
#include "core/render/cluster.h"
#include "core/scene/source_location.h"
#ifdef CAUSTICA_HAVE_MPI
#include "app/mpi_cluster.h"
#endif

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
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
    "  caustica compare IMAGE REFERENCE                   the caustic error of an image (docs/ACCURACY.md)\n"
    "  caustica --help | --version\n"
    "\n"
    "'caustica render --help' lists the options.\n";

/// `caustica render`, under mpirun with the other ranks (docs/SCALING.md).
int render_command(const std::vector<std::string>& args) {
#ifdef CAUSTICA_HAVE_MPI
    if (caustica::launched_by_mpirun()) {
        std::unique_ptr<caustica::Cluster> cluster = caustica::start_mpi_cluster();
        try {
            return caustica::run_render_command(args, cluster.get());
        } catch (const std::exception& e) {
            // Every failure the ranks can agree on was reported; this one left the other ranks
            // waiting: end them all, with the message.
            std::fprintf(stderr, "caustica: rank %d of %d: %s\n", cluster->rank(), cluster->size(), e.what());
            caustica::abort_mpi(caustica::exit_failure);
        }
    }
#else
    if (std::getenv("OMPI_COMM_WORLD_SIZE") && std::getenv("OMPI_COMM_WORLD_RANK") &&
        std::string(std::getenv("OMPI_COMM_WORLD_SIZE")) != "1") {
        if (std::string(std::getenv("OMPI_COMM_WORLD_RANK")) != "0") return caustica::exit_ok;  // rank 0 renders alone
        std::fprintf(stderr, "warning: this caustica was built without MPI: rank 0 renders alone (install "
                             "libopenmpi-dev and rebuild to share the work)\n");
    }
#endif
    return caustica::run_render_command(args);
}

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
        const bool render = command == "render";
        if (render || (command.size() > 4 && command.compare(command.size() - 4, 4, ".lua") == 0)) {
            const std::vector<std::string> render_args = render ? std::vector<std::string>(args.begin() + 1, args.end()) : args;
            return render_command(render_args);
        }
        if (command == "compare") return caustica::run_compare_command({args.begin() + 1, args.end()});
        if (command == "view") {
            // The preview is one window of one process: under mpirun every rank would open one.
            const char* ranks = std::getenv("OMPI_COMM_WORLD_SIZE");
            if (ranks && std::string(ranks) != "1") {
                const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
                if (!rank || std::string(rank) == "0")
                    std::fprintf(stderr, "caustica: view is one process with one window: start it without mpirun "
                                         "(mpirun shares 'caustica render' only)\n");
                return caustica::exit_usage;
            }
            return caustica::run_view_command({args.begin() + 1, args.end()});
        }
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
