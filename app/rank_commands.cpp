#include "app/rank_commands.h"

#include "app/render_command.h"

#include <cstddef>
#include <cstdint>

namespace caustica {
namespace {

/// The longest command line a message quotes (a scene's options can run long).
constexpr std::size_t max_quoted_command = 120;

/// The ranks whose command a message lists; any further ones are counted.
constexpr std::size_t max_listed_ranks = 4;

bool ends_with_lua(const std::string& word) {
    return word.size() > 4 && word.compare(word.size() - 4, 4, ".lua") == 0;
}

/// `caustica ARGS...` as a message quotes it, clipped.
std::string quoted_command(const std::vector<std::string>& args) {
    std::string line = "caustica";
    for (const std::string& arg : args) {
        line += ' ';
        line += arg;
        if (line.size() > max_quoted_command) break;
    }
    if (line.size() > max_quoted_command) line = line.substr(0, max_quoted_command) + "...";
    return "'" + line + "'";
}

/// What a rank sends: its command's kind, then its command line as a message quotes it.
Cluster::Bytes command_bytes(const std::vector<std::string>& args) {
    const std::string quoted = quoted_command(args);
    Cluster::Bytes bytes{static_cast<std::uint8_t>(command_kind(args))};
    bytes.insert(bytes.end(), quoted.begin(), quoted.end());
    return bytes;
}

/// The command line in a rank's bytes (empty bytes: nothing said).
std::string quoted_of(const Cluster::Bytes& bytes) {
    return bytes.empty() ? std::string("''") : std::string(bytes.begin() + 1, bytes.end());
}

/// "rank 1 of 4 was given 'caustica --version', rank 3 'caustica view', where rank 0 was given
/// 'caustica render a.lua': ...", for the ranks in `differing` (rank order, at least one).
std::string mismatch_message(const std::vector<Cluster::Bytes>& commands, const std::vector<std::size_t>& differing) {
    std::string message;
    for (std::size_t i = 0; i < differing.size() && i < max_listed_ranks; ++i) {
        const std::size_t r = differing[i];
        message += i == 0 ? "rank " + std::to_string(r) + " of " + std::to_string(commands.size()) + " was given "
                          : ", rank " + std::to_string(r) + " ";
        message += quoted_of(commands[r]);
    }
    if (differing.size() > max_listed_ranks)
        message += " (and " + std::to_string(differing.size() - max_listed_ranks) + " more ranks)";
    message += ", where rank 0 was given " + quoted_of(commands[0]) +
               ": under mpirun every rank must be given the same command";
    return message;
}

}  // namespace

CommandKind command_kind(const std::vector<std::string>& args) {
    if (args.empty()) return CommandKind::none;
    const std::string& command = args[0];
    if (command == "-h" || command == "--help" || command == "help") return CommandKind::help;
    if (command == "--version") return CommandKind::version;
    if (command == "render" || ends_with_lua(command)) return CommandKind::render;
    if (command == "compare") return CommandKind::compare;
    if (command == "view") return CommandKind::view;
    return CommandKind::unknown;
}

std::optional<RankFailure> agree_on_command(Cluster& cluster, const std::vector<std::string>& args) {
    if (cluster.size() <= 1) return std::nullopt;
    const std::vector<Cluster::Bytes> commands = cluster.all_gather(command_bytes(args));
    auto kind = [&](std::size_t r) { return commands[r].empty() ? -1 : int(commands[r][0]); };
    std::vector<std::size_t> differing;
    for (std::size_t r = 1; r < commands.size(); ++r)
        if (kind(r) != kind(0)) differing.push_back(r);
    if (differing.empty()) return std::nullopt;
    return RankFailure{static_cast<int>(differing.front()), exit_usage, mismatch_message(commands, differing)};
}

}  // namespace caustica
