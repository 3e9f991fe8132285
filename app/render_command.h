// `caustica render`: batch rendering of every gr.render in a scene script.
#pragma once

#include <string>
#include <vector>

namespace caustica {

/// Exit codes of the command line.
inline constexpr int exit_ok = 0;
inline constexpr int exit_failure = 1;      ///< an environment failure (cannot write the output)
inline constexpr int exit_usage = 2;        ///< scene or usage error
inline constexpr int exit_interrupted = 130;

class Cluster;

/// Runs `caustica render ARGS...`; returns the process exit code. With a `cluster` of several ranks
/// (mpirun, docs/SCALING.md) every rank runs it with the same arguments: they render together and
/// rank 0 writes the files and speaks; a failure on any rank ends every rank with its message.
int run_render_command(const std::vector<std::string>& args, Cluster* cluster = nullptr);

/// The text of `caustica render --help`.
std::string render_help();

}  // namespace caustica
