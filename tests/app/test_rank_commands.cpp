// Under mpirun every rank compares its command with the others' before anything else
// (app/rank_commands.h; docs/RELIABILITY.md, "Under mpirun, one rank's failure is every rank's"),
// here with threads standing in for the ranks (make_local_cluster). The same with real processes:
// tests/app/test_mpi.cpp.
#include "app/rank_commands.h"
#include "app/render_command.h"

#include <gtest/gtest.h>

#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

using namespace caustica;

namespace {

using Args = std::vector<std::string>;

/// agree_on_command on a local cluster of commands.size() ranks, rank k given commands[k]: what
/// each rank got back.
std::vector<std::optional<RankFailure>> agree(const std::vector<Args>& commands) {
    const int ranks = static_cast<int>(commands.size());
    std::vector<std::unique_ptr<Cluster>> cluster = make_local_cluster(ranks);
    std::vector<std::optional<RankFailure>> results(commands.size());
    std::vector<std::thread> threads;
    for (std::size_t r = 0; r < commands.size(); ++r)
        threads.emplace_back([&, r] { results[r] = agree_on_command(*cluster[r], commands[r]); });
    for (std::thread& t : threads) t.join();
    return results;
}

bool says(const RankFailure& failure, const std::string& text) {
    return failure.message.find(text) != std::string::npos;
}

}  // namespace

TEST(RankCommands, TheCommandIsNamedByTheFirstWord) {
    EXPECT_EQ(command_kind({}), CommandKind::none);
    for (const char* help : {"-h", "--help", "help"}) EXPECT_EQ(command_kind({help}), CommandKind::help) << help;
    EXPECT_EQ(command_kind({"--version"}), CommandKind::version);
    EXPECT_EQ(command_kind({"render", "--help"}), CommandKind::render);
    EXPECT_EQ(command_kind({"scene.lua", "-o", "x.png"}), CommandKind::render);
    EXPECT_EQ(command_kind({"compare", "a.png", "b.png"}), CommandKind::compare);
    EXPECT_EQ(command_kind({"view"}), CommandKind::view);
    EXPECT_EQ(command_kind({".lua"}), CommandKind::unknown);
    EXPECT_EQ(command_kind({"rendre", "a.lua"}), CommandKind::unknown);
}

TEST(RankCommands, TheSameCommandOnEveryRankGoesOn) {
    // A render's own arguments may differ here: the render compares them and its scene itself
    // (its --help and its plan: app/render_command.cpp).
    for (const std::optional<RankFailure>& result :
         agree({{"render", "a.lua", "-o", "x.png"}, {"a.lua", "-o", "x.png"}, {"render", "--help"}}))
        EXPECT_FALSE(result.has_value()) << result->message;
    for (const std::optional<RankFailure>& result : agree({{"--version"}, {"--version"}}))
        EXPECT_FALSE(result.has_value()) << result->message;
}

TEST(RankCommands, ARankGivenAnotherCommandStopsEveryRankNamingItsCommand) {
    for (const Args& other : {Args{"--version"}, Args{"--help"}, Args{"rendre", "a.lua"}, Args{"view"}, Args{}}) {
        const std::vector<std::optional<RankFailure>> results = agree({{"render", "a.lua", "-o", "x.png"}, other});
        std::string quoted = "'caustica";
        for (const std::string& arg : other) quoted += " " + arg;
        quoted += "'";
        for (const std::optional<RankFailure>& result : results) {
            ASSERT_TRUE(result.has_value()) << quoted;
            EXPECT_EQ(result->rank, 1);
            EXPECT_EQ(result->exit_code, exit_usage);
            EXPECT_EQ(result->message, "rank 1 of 2 was given " + quoted +
                                           ", where rank 0 was given 'caustica render a.lua -o x.png': under mpirun "
                                           "every rank must be given the same command");
        }
    }
}

TEST(RankCommands, EveryRankThatDiffersFromRankZeroIsNamed) {
    const std::vector<std::optional<RankFailure>> results =
        agree({{"a.lua"}, {"--version"}, {"render", "a.lua"}, {"view", "a.lua"}});
    for (const std::optional<RankFailure>& result : results) {
        ASSERT_TRUE(result.has_value());
        EXPECT_EQ(result->rank, 1);
        EXPECT_EQ(result->message, "rank 1 of 4 was given 'caustica --version', rank 3 'caustica view a.lua', where "
                                   "rank 0 was given 'caustica a.lua': under mpirun every rank must be given the same "
                                   "command");
    }
}

TEST(RankCommands, ManyDifferingRanksAndLongCommandsKeepTheMessageShort) {
    std::vector<Args> commands(8, Args{"--version"});
    commands[0] = Args{"render", "a.lua", "--allow-read", std::string(500, 'd')};
    const std::vector<std::optional<RankFailure>> results = agree(commands);
    ASSERT_TRUE(results[5].has_value());
    const RankFailure& failure = *results[5];
    EXPECT_TRUE(says(failure, "rank 1 of 8 was given 'caustica --version', rank 2 'caustica --version'"))
        << failure.message;
    EXPECT_TRUE(says(failure, "rank 4 'caustica --version' (and 3 more ranks)")) << failure.message;
    EXPECT_FALSE(says(failure, "rank 5")) << failure.message;
    EXPECT_TRUE(says(failure, "where rank 0 was given 'caustica render a.lua --allow-read ddd")) << failure.message;
    EXPECT_LT(failure.message.size(), 400u) << failure.message;
}
