// Runs a shell command for the tests that drive the built binary (test_cli, test_animation,
// test_mpi): its exit code and everything it printed (stdout and stderr).
#pragma once

#include <cstdio>
#include <string>

#include <sys/wait.h>

namespace caustica::testing {

struct CommandResult {
    int code = -1;  ///< exit code, -1 when killed by a signal
    std::string output;
};

inline CommandResult run_shell(const std::string& command) {
    CommandResult r;
    FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
    if (!pipe) return r;
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
    const int status = ::pclose(pipe);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

}  // namespace caustica::testing
