#include "app/view_command.h"

#include "app/render_command.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <unistd.h>

namespace caustica {

int run_view_command(const std::vector<std::string>& args) {
    namespace fs = std::filesystem;
    const char* display = std::getenv("DISPLAY");
    const bool asked = std::find(args.begin(), args.end(), "--headless") != args.end();
    const bool headless = asked || !display || !*display;
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec) {
        std::fprintf(stderr, "caustica view: cannot find this executable's folder (%s)\n", ec.message().c_str());
        return exit_failure;
    }
    const fs::path program = self.parent_path() / (headless ? "caustica-view-headless" : "caustica-view");
    if (!fs::exists(program, ec)) {
        std::fprintf(stderr, "caustica view: %s is missing; build it (target %s)\n", program.c_str(),
                     program.filename().c_str());
        return exit_failure;
    }
    if (headless && !asked)
        std::fprintf(stderr, "caustica view: no DISPLAY, so no window: the preview runs headless (OSMesa)\n");
    std::vector<std::string> arguments{program.string()};
    arguments.insert(arguments.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : arguments) argv.push_back(a.data());
    argv.push_back(nullptr);
    std::fflush(stdout);
    std::fflush(stderr);
    ::execv(program.c_str(), argv.data());
    std::fprintf(stderr, "caustica view: cannot run %s: %s\n", program.c_str(), std::strerror(errno));
    return exit_failure;
}

}  // namespace caustica
