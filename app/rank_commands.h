// Which command the command line names, and, under mpirun, the agreement that every rank was given
// the same one (docs/RELIABILITY.md, "Under mpirun, one rank's failure is every rank's").
#pragma once

#include "core/render/cluster.h"

#include <optional>
#include <string>
#include <vector>

namespace caustica {

/// The commands of `caustica ARGS...` (app/main.cpp runs them).
enum class CommandKind { none, help, version, render, compare, view, unknown };

/// The command `args` (argv without the program name) names: `render ...` and `SCENE.lua ...` are
/// both render; nothing at all is `none`.
CommandKind command_kind(const std::vector<std::string>& args);

/// Collective, the first thing every rank does under mpirun: every rank's command. Nothing when
/// every rank was given the same command (a render then compares its arguments and scene itself);
/// otherwise the same failure on every rank (exit 2), naming each rank whose command differs from
/// rank 0's, what it was given and what rank 0 was given. A rank that ended without taking part
/// would leave the others waiting for it for ever.
std::optional<RankFailure> agree_on_command(Cluster& cluster, const std::vector<std::string>& args);

}  // namespace caustica
