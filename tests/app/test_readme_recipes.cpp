// The README's usage recipes, run as written (read from README.md itself, so that a recipe cannot
// change without its test), made small: every render at --minres with fewer photons, long
// stopping rules shortened (--time 60 to 2 s, --target-error 0.05 to 0.3, 120 orbit frames to 3).
// Each must exit 0, write what it names, and stop by the rule it was given.
#include "tests/course_scenes.h"
#include "tests/run_command.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

const std::string source_dir = CAUSTICA_SOURCE_DIR;

/// The `build/caustica ...` and `mpirun ... build/caustica ...` lines of README.md's usage block.
std::vector<std::string> readme_recipes() {
    std::ifstream in(source_dir + "/README.md");
    std::vector<std::string> recipes;
    std::string line;
    while (std::getline(in, line)) {
        const std::size_t at = line.find("build/caustica ");
        // (The synopsis line, with its [options], is not a recipe.)
        if (line.rfind("    ", 0) != 0 || at == std::string::npos || line.find("[options]") != std::string::npos) continue;
        std::string recipe = line.substr(4);
        if (const std::size_t comment = recipe.find("  #"); comment != std::string::npos) recipe.resize(comment);
        while (!recipe.empty() && recipe.back() == ' ') recipe.pop_back();
        recipes.push_back(recipe);
    }
    return recipes;
}

/// `text` with every match of `pattern` replaced.
std::string replace(const std::string& text, const std::string& pattern, const std::string& with) {
    return std::regex_replace(text, std::regex(pattern), with);
}

struct Recipe {
    std::string written;  ///< as the README writes it
    std::string command;  ///< what the test runs
    std::string output;   ///< the file it must write ("" when it names none)
};

/// A recipe made small enough for the suite: its own options kept, a smaller image and photon
/// count added (the last option given wins), its long rules shortened.
Recipe small(const std::string& written) {
    Recipe r{written, written, ""};
    std::smatch m;
    if (std::regex_search(written, m, std::regex(R"(-o (\S+))"))) r.output = m[1];
    if (std::regex_search(written, m, std::regex(R"(--snapshot (\S+))"))) r.output = m[1];
    std::string c = replace(written, R"(build/caustica)", "'" CAUSTICA_BINARY "'");
    // The mpirun the build found (the one test_mpi.cpp uses), not whichever comes first in PATH.
    // Under AddressSanitizer the ranks unwind allocations fully, as test_mpi.cpp has them do, so
    // that what Open MPI's unloaded plugins leave is seen to come from Open MPI (tests/lsan.supp).
    if (c.rfind("mpirun ", 0) == 0) {
        c = "'" CAUSTICA_MPIRUN "'" + c.substr(6);
        if (const char* asan = std::getenv("ASAN_OPTIONS"))
            c = "ASAN_OPTIONS='" + std::string(asan) + ":fast_unwind_on_malloc=0' " + c;
    }
    c = replace(c, R"(--time 60)", "--time 2");
    c = replace(c, R"(--target-error 0\.05)", "--target-error 0.3");
    c = replace(c, R"(--orbit-frames 120)", "--orbit-frames 3");
    const std::string course_scenes = caustica::testing::cs488_dir() + "/", shared = source_dir + "/../shared/";
    c = replace(c, R"(( )\.\./shared/cs488/)", "$1" + course_scenes);
    c = replace(c, R"(( )\.\./shared/)", "$1" + shared);
    c = replace(c, R"( scenes/)", " " + source_dir + "/scenes/");
    const bool render = c.find(" render ") != std::string::npos;
    const bool photons_given = c.find("--caustic-num-photons") != std::string::npos;
    if (render) {
        std::string extra = " --minres";
        if (!photons_given) extra += " --caustic-num-photons 200000";
        if (c.find("--gi-num-photons") == std::string::npos) extra += " --gi-num-photons 200000";
        c = replace(c, " render ", " render" + extra + " ");
    }
    r.command = c;
    return r;
}

class ReadmeRecipes : public ::testing::TestWithParam<std::string> {};

}  // namespace

TEST(ReadmeRecipesList, TheUsageBlockHasTheRecipesThisFileRuns) {
    const std::vector<std::string> recipes = readme_recipes();
    ASSERT_GE(recipes.size(), 10u);
    bool time_rule = false, error_rule = false;
    for (const std::string& r : recipes) {
        time_rule |= r.find("--time 60") != std::string::npos && r.find("--passes") == std::string::npos;
        error_rule |= r.find("--target-error") != std::string::npos && r.find("--passes") == std::string::npos;
    }
    EXPECT_TRUE(time_rule) << "the README's converged-image recipe (--time alone) is gone";
    EXPECT_TRUE(error_rule) << "the README's target-error recipe (--target-error alone) is gone";
}

TEST_P(ReadmeRecipes, RunsAsWrittenAndStopsByItsRule) {
    const Recipe recipe = small(GetParam());
    if (recipe.written.find("../shared/") != std::string::npos && !caustica::testing::have_cs488())
        GTEST_SKIP() << "../shared is not beside this clone: " << recipe.written;
    if (recipe.written.rfind("mpirun", 0) == 0 && std::string(CAUSTICA_MPIRUN).empty())
        GTEST_SKIP() << "caustica was built without MPI (Open MPI is optional): " << recipe.written;
    if (recipe.written.find(" view ") != std::string::npos && recipe.written.find("--headless") == std::string::npos)
        GTEST_SKIP() << "opens a window (the preview's own tests run it under Xvfb): " << recipe.written;
    const fs::path dir = fs::temp_directory_path() / ("caustica_readme_" + std::to_string(::getpid()) + "_" +
                                                      std::to_string(std::hash<std::string>{}(recipe.written)));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::string command = recipe.command;
    // The timed recipes print their statistics, so that the rule that stopped them can be read.
    const bool accumulates = command.find("--time") != std::string::npos || command.find("--target-error") != std::string::npos;
    if (accumulates && command.find(" -S") == std::string::npos) command = replace(command, " render ", " render -S ");
    // A target the estimate never reaches must fail the test, not hang it.
    if (command.find("--target-error") != std::string::npos && command.find("--time") == std::string::npos)
        command = replace(command, " render ", " render --time 60 ");
    const caustica::testing::CommandResult r = caustica::testing::run_shell("cd '" + dir.string() + "' && " + command);
    EXPECT_EQ(r.code, 0) << recipe.written << "\nran: " << command << "\n" << r.output;
    if (!recipe.output.empty()) {
        if (recipe.written.find("--orbit-frames") != std::string::npos)
            EXPECT_TRUE(fs::exists(dir / "turn" / "f-0003.png")) << r.output;
        else
            EXPECT_TRUE(fs::exists(dir / recipe.output)) << recipe.output << "\n" << r.output;
    }
    std::smatch m;
    const std::regex passes_line(R"(progressive passes\s+(\d+) \(stopped by ([a-z ]+)\))");
    if (recipe.written.find("--time") != std::string::npos) {
        // --time alone means "until that time": more than the one pass --passes defaults to.
        ASSERT_TRUE(std::regex_search(r.output, m, passes_line)) << r.output;
        EXPECT_EQ(m[2].str(), "time") << r.output;
        EXPECT_GT(std::stoi(m[1].str()), 1) << r.output;
    }
    if (recipe.written.find("--target-error") != std::string::npos) {
        ASSERT_TRUE(std::regex_search(r.output, m, passes_line)) << r.output;
        EXPECT_EQ(m[2].str(), "target error") << r.output;
    }
    fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Readme, ReadmeRecipes, ::testing::ValuesIn(readme_recipes()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             return "recipe" + std::to_string(info.index);
                         });
