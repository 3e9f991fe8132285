// caustica: the command-line entry point. Subcommands as in yocto's apps: render, view.
#include "app/compare_command.h"
#include "app/rank_commands.h"
#include "app/render_command.h"
#include "app/view_command.h"
#include "core/render/cluster.h"
#include "core/scene/source_location.h"
#include "core/util/printable_text.h"
#ifdef CAUSTICA_HAVE_MPI
#include "app/mpi_cluster.h"
#endif

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <new>
#include <optional>
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

/// `caustica render`; under mpirun `cluster` holds the ranks (docs/SCALING.md).
int render_command(const std::vector<std::string>& args, caustica::Cluster* cluster) {
#ifdef CAUSTICA_HAVE_MPI
    if (cluster) {
        try {
            return caustica::run_render_command(args, cluster);
        } catch (const std::exception& e) {
            // Every failure the ranks can agree on was reported; this one left the other ranks
            // waiting: end them all, with the message.
            std::fprintf(stderr, "caustica: rank %d of %d: %s\n", cluster->rank(), cluster->size(),
                         caustica::printable_text(e.what()).c_str());
            caustica::abort_mpi(caustica::exit_failure);
        }
    }
#else
    (void)cluster;
    if (std::getenv("OMPI_COMM_WORLD_SIZE") && std::getenv("OMPI_COMM_WORLD_RANK") &&
        std::string(std::getenv("OMPI_COMM_WORLD_SIZE")) != "1") {
        if (std::string(std::getenv("OMPI_COMM_WORLD_RANK")) != "0") return caustica::exit_ok;  // rank 0 renders alone
        std::fprintf(stderr, "warning: this caustica was built without MPI: rank 0 renders alone (install "
                             "libopenmpi-dev and rebuild to share the work)\n");
    }
#endif
    return caustica::run_render_command(args);
}

/// Runs the command `args` names and returns the exit code; under mpirun `cluster` holds the
/// ranks, every one of them given the same command.
int run_command(const std::vector<std::string>& args, caustica::Cluster* cluster) {
    try {
        switch (caustica::command_kind(args)) {
        case caustica::CommandKind::none:
            std::fprintf(stderr, "%s", usage);
            return caustica::exit_usage;
        case caustica::CommandKind::help:
            std::printf("%s", usage);
            return caustica::exit_ok;
        case caustica::CommandKind::version:
            std::printf("caustica %s\n", CAUSTICA_VERSION);
            return caustica::exit_ok;
        case caustica::CommandKind::render:
            return render_command(args[0] == "render" ? std::vector<std::string>(args.begin() + 1, args.end()) : args,
                                  cluster);
        case caustica::CommandKind::compare:
            return caustica::run_compare_command({args.begin() + 1, args.end()});
        case caustica::CommandKind::view: {
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
        case caustica::CommandKind::unknown:
            break;
        }
        std::fprintf(stderr, "caustica: unknown command '%s'\n\n%s", args[0].c_str(), usage);
        return caustica::exit_usage;
    } catch (const std::bad_alloc&) {
        // Only reached when no stage could name the cause: still a clear message, exit 2 (README).
        std::fprintf(stderr, "caustica: not enough memory for this scene (an allocation failed)\n");
        return caustica::exit_usage;
    } catch (const caustica::InputError& e) {
        std::fprintf(stderr, "caustica: %s\n", caustica::printable_text(e.what()).c_str());
        return caustica::exit_usage;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "caustica: %s\n", caustica::printable_text(e.what()).c_str());
        return caustica::exit_failure;
    }
}

#ifdef CAUSTICA_HAVE_MPI
/// Under mpirun every rank starts MPI and compares its command with the others' before anything
/// else, whatever the command: a rank that ended without taking part (given --version while the
/// others render) would leave them waiting for ever (docs/RELIABILITY.md, "Under mpirun, one
/// rank's failure is every rank's"). MPI ends when the command returns.
int run_with_ranks(const std::vector<std::string>& args) {
    std::unique_ptr<caustica::Cluster> cluster;
    try {
        cluster = caustica::start_mpi_cluster();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "caustica: %s\n", e.what());
        return caustica::exit_failure;
    }
    if (const std::optional<caustica::RankFailure> failure = caustica::agree_on_command(*cluster, args)) {
        if (cluster->rank() == 0) std::fprintf(stderr, "caustica: %s\n", failure->message.c_str());
        return failure->exit_code;
    }
    return run_command(args, cluster.get());
}
#endif

}  // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> args(argv + 1, argv + argc);
#ifdef CAUSTICA_HAVE_MPI
    if (caustica::launched_by_mpirun()) return run_with_ranks(args);
#endif
    return run_command(args, nullptr);
}
