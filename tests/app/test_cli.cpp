// The command line as a user meets it: exit codes, messages naming file:line, no partial output,
// Ctrl-C, precedence of the command line over gr.option, PNG metadata.
#include "core/io/png_io.h"
#include "core/util/sanitized.h"

#include "tests/run_command.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <spawn.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char** environ;

namespace fs = std::filesystem;

namespace {

struct Result {
    int code = -1;
    std::string output;  // stdout and stderr together
};

class Cli : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("caustica_cli_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }

    Result run(const std::string& args) {
        const caustica::testing::CommandResult r =
            caustica::testing::run_shell("cd '" + dir_.string() + "' && '" CAUSTICA_BINARY "' " + args);
        return {r.code, r.output};
    }

    bool exists(const std::string& name) const { return fs::exists(dir_ / name); }

    /// No file at all other than the inputs (no partial output, no temporary left behind).
    std::vector<std::string> pngs() const {
        std::vector<std::string> found;
        for (const auto& entry : fs::directory_iterator(dir_))
            if (entry.path().filename().string().find(".png") != std::string::npos)
                found.push_back(entry.path().filename().string());
        return found;
    }

    fs::path dir_;
};

const char* small_scene =
    "m = gr.material({0.8, 0.2, 0.2}, {0.3, 0.3, 0.3}, 20)\n"
    "s = gr.nh_sphere('s', {0, 0, 0}, 1)\n"
    "s:set_material(m)\n"
    "root = gr.node('root')\n"
    "root:add_child(s)\n"
    "l = gr.light({5, 5, 5}, {1, 1, 1}, {1, 0, 0})\n"
    "gr.render(root, 'out.png', 40, 30, {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 50, {0.1, 0.1, 0.1}, {l})\n";

}  // namespace

TEST_F(Cli, NoArgumentsIsAUsageError) {
    const Result r = run("");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("usage:"), std::string::npos);
}

TEST_F(Cli, HelpListsTheOptions) {
    const Result r = run("render --help");
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.output.find("--caustic-num-photons"), std::string::npos);
    EXPECT_NE(r.output.find("-o OUT.png"), std::string::npos);
    for (const char* option : {"--tonemap", "--exposure", "--exr-pixel", "OUT.exr", "OUT.pfm"})
        EXPECT_NE(r.output.find(option), std::string::npos) << option;
    EXPECT_EQ(run("--help").code, 0);
}

// The help speaks the project's own language: the classic rules by their names in
// docs/CAUSTICS.md, never by codes of a page outside the repository or issue numbers.
TEST_F(Cli, HelpCitesNoRuleCodesOrIssues) {
    for (const char* command : {"--help", "render --help", "view --help"}) {
        const Result r = run(command);
        EXPECT_EQ(r.code, 0) << command;
        const std::regex outside(R"(\b[AB][0-9]\b|SEED_BEHAVIOUR|Part [AB]\b|[Ii]ssue [0-9]|\.\./shared)");
        // "CS488 A4" is the course's assignment, which --a4 is named after, not a rule code.
        const std::string text = std::regex_replace(r.output, std::regex("CS488 A4"), "CS488");
        std::smatch found;
        EXPECT_FALSE(std::regex_search(text, found, outside)) << command << ": '" << found.str() << "'";
    }
}

TEST_F(Cli, ViewRefusesAMissingSceneBeforeOpeningAWindow) {
    const Result r = run("view missing.lua");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("no such scene file"), std::string::npos) << r.output;
}

TEST_F(Cli, RendersAndWritesThePngTheScriptNames) {
    write("scene.lua", small_scene);
    const Result r = run("render scene.lua");
    ASSERT_EQ(r.code, 0) << r.output;
    ASSERT_TRUE(exists("out.png"));
    const caustica::Png8 png = caustica::read_png((dir_ / "out.png").string());
    EXPECT_EQ(png.width, 40);
    EXPECT_EQ(png.height, 30);
    bool has_software = false, has_source = false;
    for (const auto& [key, value] : png.text) {
        has_software |= key == "Software" && value.rfind("caustica", 0) == 0;
        has_source |= key == "Source" && value == "scene.lua";
    }
    EXPECT_TRUE(has_software);
    EXPECT_TRUE(has_source);
    EXPECT_EQ(pngs(), std::vector<std::string>{"out.png"});  // no temporary left behind
}

TEST_F(Cli, OutputFlagOverridesAndNumbersSeveralRenders) {
    write("scene.lua", std::string(small_scene) +
                           "gr.render(root, 'two.png', 20, 10, {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 50, {0, 0, 0}, {l})\n");
    ASSERT_EQ(run("render scene.lua -o x.png").code, 0);
    EXPECT_TRUE(exists("x-1.png"));
    EXPECT_TRUE(exists("x-2.png"));
    EXPECT_FALSE(exists("out.png"));
    EXPECT_EQ(caustica::read_png((dir_ / "x-2.png").string()).width, 20);
}

TEST_F(Cli, CommandLineWinsOverGrOption) {
    write("scene.lua", std::string("gr.option('--minres')\n") + small_scene);
    ASSERT_EQ(run("render scene.lua").code, 0);
    EXPECT_EQ(caustica::read_png((dir_ / "out.png").string()).width, 100);
    ASSERT_EQ(run("render --lores scene.lua").code, 0);
    EXPECT_EQ(caustica::read_png((dir_ / "out.png").string()).width, 256);
}

TEST_F(Cli, AProjectSceneChoosesItsIntegratorWithGrOptionAndTheCommandLineWins) {
    // scenes/glass_of_liquid.lua sets --integrator progressive with gr.option (its shadow caustic);
    // a --integrator on the command line wins over it, as over any gr.option.
    const std::string scene = "'" CAUSTICA_SOURCE_DIR "/scenes/glass_of_liquid.lua'";
    auto integrator_of = [&](const std::string& name) {
        for (const auto& [key, value] : caustica::read_png((dir_ / name).string()).text)
            if (key == "caustica:integrator") return value;
        return std::string("(missing)");
    };
    const std::string small = "render -s --minres --threads 2 --caustic-num-photons 100000 ";
    ASSERT_EQ(run(small + scene + " -o own.png").code, 0);
    EXPECT_EQ(integrator_of("own.png"), "progressive");
    ASSERT_EQ(run(small + "--integrator classic " + scene + " -o classic.png").code, 0);
    EXPECT_EQ(integrator_of("classic.png"), "classic");
}

TEST_F(Cli, LayersAreWrittenToAMultilayerExrOnly) {
    write("scene.lua", small_scene);
    const Result png = run("render --layers scene.lua -o x.png");
    EXPECT_EQ(png.code, 2);
    EXPECT_NE(png.output.find("--layers: 'x.png': layers need an OpenEXR output (.exr)"), std::string::npos) << png.output;
    EXPECT_TRUE(pngs().empty());
    // Given in the script, the refusal names the gr.render that would write the PNG.
    write("named.lua", std::string("gr.option('--layers')\n") + small_scene);
    const Result named = run("render named.lua");
    EXPECT_EQ(named.code, 2);
    EXPECT_NE(named.output.find("named.lua:8: gr.render: --layers: 'out.png'"), std::string::npos) << named.output;
    EXPECT_TRUE(pngs().empty());

    ASSERT_EQ(run("render --layers scene.lua -o x.exr").code, 0);
    Imf::InputFile file((dir_ / "x.exr").c_str());
    std::vector<std::string> names;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) names.push_back(it.name());
    for (const char* name : {"R", "G", "B", "A", "direct.R", "indirect.G", "caustic.B", "background.R", "albedo.G", "normal.Z"})
        EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
    EXPECT_EQ(names.size(), 22u);

    // A progressive accumulation writes its accumulated layers; a continued one has none to give.
    ASSERT_EQ(run("render --layers --integrator progressive --passes 3 scene.lua -o passes.exr").code, 0);
    Imf::InputFile accumulated((dir_ / "passes.exr").c_str());
    std::size_t channels = 0;
    for (auto it = accumulated.header().channels().begin(); it != accumulated.header().channels().end(); ++it) ++channels;
    EXPECT_EQ(channels, 22u);
    const Result resumed = run("render --layers --resume --integrator progressive --passes 3 scene.lua -o again.exr");
    EXPECT_EQ(resumed.code, 2);
    EXPECT_NE(resumed.output.find("--resume: a saved accumulation holds no layers"), std::string::npos) << resumed.output;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "again.exr"));
}

TEST_F(Cli, MissingSceneFile) {
    const Result r = run("render nothere.lua");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("nothere.lua: no such scene file"), std::string::npos) << r.output;
}

TEST_F(Cli, UnknownOptionSuggestsAndRendersNothing) {
    write("scene.lua", small_scene);
    const Result r = run("render --aa-gird 4 scene.lua");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("did you mean --aa-grid?"), std::string::npos) << r.output;
    EXPECT_TRUE(pngs().empty());
}

TEST_F(Cli, SceneErrorNamesFileAndLineAndWritesNothing) {
    write("bad.lua", std::string(small_scene) + "m2 = gr.material({1, 1}, {0, 0, 0}, 10)\n");
    const Result r = run("render bad.lua");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("bad.lua:8: gr.material:"), std::string::npos) << r.output;
    EXPECT_TRUE(pngs().empty());
}

TEST_F(Cli, SyntaxErrorNamesTheLine) {
    write("syntax.lua", "x = 1\ny = = 2\n");
    const Result r = run("render syntax.lua");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("syntax.lua:2:"), std::string::npos) << r.output;
}

TEST_F(Cli, ScriptTextReachesTheTerminalWithItsEscapesMadeVisible) {
    // A node name the renderer quotes in a warning, print output and a script error: each with
    // escape sequences (screen clear, window title, clipboard write) that must not reach the
    // terminal as such (docs/RELIABILITY.md, "Script text reaches the user bounded and visible").
    write("escapes.lua",
          "s = gr.nh_sphere('\\27]0;title\\7ball', {0, 0, 0}, 1)\n"
          "root = gr.node('root')\n"
          "root:add_child(s)\n"
          "l = gr.light({5, 5, 5}, {1, 1, 1}, {1, 0, 0})\n"
          "print('\\27[2J café')\n"
          "gr.render(root, 'out.png', 8, 8, {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 50, {0.1, 0.1, 0.1}, {l})\n");
    const Result r = run("render escapes.lua");
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("\\x1b[2J café\n"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("escapes.lua:1: node '\\x1b]0;title\\x07ball' has no material"), std::string::npos)
        << r.output;
    write("error.lua", "error('\\27]52;c;ZXZpbA==\\7')\n");
    const Result failed = run("render error.lua");
    EXPECT_EQ(failed.code, 2);
    EXPECT_NE(failed.output.find("error.lua:1: \\x1b]52;c;ZXZpbA==\\x07"), std::string::npos) << failed.output;
    for (const std::string& output : {r.output, failed.output})
        EXPECT_EQ(std::count_if(output.begin(), output.end(), [](char c) { return c == '\x1b' || c == '\x07'; }), 0)
            << output;
}

TEST_F(Cli, UnwritableOutputFolderIsRefusedBeforeRendering) {
    // Exit 1, "the output could not be written" (README), as when the write fails after rendering.
    std::string scene = small_scene;
    scene.replace(scene.find("'out.png'"), 9, "'nodir/out.png'");
    write("scene.lua", scene);
    const Result r = run("render scene.lua");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.output.find("scene.lua:7: gr.render: cannot write 'nodir/out.png': folder 'nodir' does not exist"),
              std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("wrote"), std::string::npos) << r.output;
}

TEST_F(Cli, EveryOutputThatCannotBeWrittenExits1BeforeRendering) {
    write("scene.lua", small_scene);
    fs::create_directory(dir_ / "taken.png");
    const std::string long_name(300, 'n');
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"nodir/x.png", "-o: cannot write 'nodir/x.png': folder 'nodir' does not exist"},
        {"taken.png", "-o: cannot write 'taken.png': it is a folder"},
        {"/proc/x.png", "-o: cannot write '/proc/x.png': No such file or directory"},  // root may "write" there
        {long_name + ".png", "-o: cannot write '" + long_name + ".png': File name too long"},
    };
    for (const auto& [output, message] : cases) {
        const Result r = run("render -v scene.lua -o '" + output + "'");
        EXPECT_EQ(r.code, 1) << output << ": " << r.output;
        EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
        EXPECT_EQ(r.output.find("rendering"), std::string::npos) << "refused after starting: " << r.output;
    }
    EXPECT_TRUE(pngs() == std::vector<std::string>{"taken.png"});
}

TEST_F(Cli, AnOutputFolderRemovedDuringTheRenderExits1Too) {
    std::string scene = small_scene;
    scene.replace(scene.find("'out.png', 40, 30"), 17, "'sub/out.png', 1500, 1500");
    write("scene.lua", "gr.option('--aa-grid 4 --aa-threshold 0 --threads 2')\n" + scene);
    fs::create_directory(dir_ / "sub");
    const std::string command = "cd '" + dir_.string() + "' && '" CAUSTICA_BINARY "' render -v scene.lua 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    std::string output;
    char line[4096];
    while (std::fgets(line, sizeof line, pipe)) {
        output += line;
        if (output.find("rendering sub/out.png") != std::string::npos) {
            fs::remove_all(dir_ / "sub");  // after the check, long before the write
            break;
        }
    }
    while (std::fgets(line, sizeof line, pipe)) output += line;
    const int status = ::pclose(pipe);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 1) << output;
    EXPECT_NE(output.find("cannot write 'sub/out.png': No such file or directory"), std::string::npos) << output;
}

TEST_F(Cli, ScriptWithoutRenderIsAnError) {
    write("empty.lua", "x = 1\n");
    const Result r = run("render empty.lua");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("no gr.render"), std::string::npos);
}

TEST_F(Cli, InterruptStopsWithinASecondExits130AndWritesNothing) {
    std::string scene = small_scene;
    scene.replace(scene.find("40, 30"), 6, "4000, 4000");
    write("big.lua", "gr.option('--aa-grid 16 --aa-threshold 0 --threads 2')\n" + scene);
    const std::string binary = CAUSTICA_BINARY;
    const std::string scene_path = (dir_ / "big.lua").string();
    const std::string out_path = (dir_ / "big.png").string();
    const char* argv[] = {binary.c_str(), "render", "-s", scene_path.c_str(), "-o", out_path.c_str(), nullptr};
    pid_t pid;
    ASSERT_EQ(::posix_spawn(&pid, binary.c_str(), nullptr, nullptr, const_cast<char**>(argv), environ), 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // well into the render
    const auto t0 = std::chrono::steady_clock::now();
    ::kill(pid, SIGINT);
    int status = 0;
    ::waitpid(pid, &status, 0);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130);
    EXPECT_LT(seconds, caustica::testing::time_bound(1.0));
    EXPECT_TRUE(pngs().empty());
}

namespace {


/// Runs `caustica render -s big.lua -o out.png` on a 4000 x 4000 image (about 1.5 s to render,
/// over a second to write), sends `signals` as soon as the PNG's temporary appears, and returns
/// the exit status and the seconds from the first signal to the exit.
std::pair<int, double> interrupt_the_write(const fs::path& dir, const std::vector<int>& signals) {
    std::string scene = small_scene;
    scene.replace(scene.find("40, 30"), 6, "4000, 4000");
    std::ofstream(dir / "big.lua") << "gr.option('--threads 2 --disable-aa')\n" + scene;  // the write is what matters
    const std::string binary = CAUSTICA_BINARY;
    const std::string scene_path = (dir / "big.lua").string();
    const std::string out_path = (dir / "out.png").string();
    const char* argv[] = {binary.c_str(), "render", "-s", scene_path.c_str(), "-o", out_path.c_str(), nullptr};
    pid_t pid;
    if (::posix_spawn(&pid, binary.c_str(), nullptr, nullptr, const_cast<char**>(argv), environ) != 0) return {-1, 0};
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    const std::string its_pid = std::string("-") + std::to_string(pid) + '-';
    bool writing = false;
    while (!writing && std::chrono::steady_clock::now() < give_up) {
        for (const auto& entry : fs::directory_iterator(dir)) {
            const std::string name = entry.path().filename().string();
            writing |= name.rfind(".out.png.caustica-tmp-", 0) == 0 && name.find(its_pid) != std::string::npos;
        }
        if (!writing) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    const auto t0 = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < signals.size(); ++i) {
        if (i > 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
        ::kill(pid, signals[i]);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return {writing && WIFEXITED(status) ? WEXITSTATUS(status) : -1, seconds};
}

}  // namespace

TEST_F(Cli, CtrlCDuringThePngWriteStopsItAndLeavesNothing) {
    const auto [code, seconds] = interrupt_the_write(dir_, {SIGINT});
    EXPECT_EQ(code, 130);
    EXPECT_LT(seconds, caustica::testing::time_bound(1.0));
    EXPECT_TRUE(pngs().empty()) << pngs()[0];  // neither out.png nor its temporary
}

TEST_F(Cli, ASecondSignalDuringThePngWriteLeavesNoTemporary) {
    for (const int sig : {SIGINT, SIGTERM}) {
        const auto [code, seconds] = interrupt_the_write(dir_, {sig, sig});
        EXPECT_EQ(code, 130) << sig;
        EXPECT_LT(seconds, caustica::testing::time_bound(1.0)) << sig;
        EXPECT_TRUE(pngs().empty()) << pngs()[0];
    }
}

TEST_F(Cli, AKilledWritesTemporaryIsRemovedByTheNextRun) {
    // SIGKILL cannot be handled: the temporary stays until the next run writing into the folder,
    // which removes it (its process is gone) and nothing else.
    std::ofstream(dir_ / ".out.png.caustica-tmp-elsewhere-1-0") << "another host's: kept";
    const auto [code, seconds] = interrupt_the_write(dir_, {SIGKILL});
    EXPECT_EQ(code, -1);  // killed
    std::vector<std::string> left = pngs();
    std::sort(left.begin(), left.end());
    ASSERT_EQ(left.size(), 2u) << "the killed run's temporary and the other host's";
    EXPECT_EQ(left[0], ".out.png.caustica-tmp-elsewhere-1-0");
    write("scene.lua", small_scene);
    ASSERT_EQ(run("render scene.lua -o other.png").code, 0);
    std::vector<std::string> after = pngs();
    std::sort(after.begin(), after.end());
    EXPECT_EQ(after, (std::vector<std::string>{".out.png.caustica-tmp-elsewhere-1-0", "other.png"}));
    (void)seconds;
}

TEST_F(Cli, RunningOutOfMemoryIsAClearSceneErrorNotABareBadAlloc) {
    if (caustica::sanitized_build) GTEST_SKIP() << "an address-space limit cannot hold a sanitizer's shadow memory";
    // 16384 x 16384 needs 3 GiB of float pixels; the process may have 1.5 GB of address space.
    std::string scene = small_scene;
    scene.replace(scene.find("40, 30"), 6, "16384, 16384");
    write("huge.lua", scene);
    const std::string command = "cd '" + dir_.string() + "' && ulimit -v 1500000 && '" CAUSTICA_BINARY
                                "' render -s huge.lua -o out.png 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    std::string output;
    char buffer[4096];
    for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
    const int status = ::pclose(pipe);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 2) << output;
    EXPECT_EQ(output, "caustica: huge.lua:7: gr.render: not enough memory to render 'out.png' (16384 x 16384 pixels); "
                      "lower the resolution or the photon count\n");
    EXPECT_TRUE(pngs().empty());
}

namespace {

/// A glass ball focusing a light onto a floor, 32 x 32: a caustic that progressive passes refine.
const char* focus_scene = R"(glass = gr.material({0, 0, 0}, {1, 1, 1}, 20)
glass:set_ri(1.5)
ball = gr.nh_sphere('ball', {0, 1.2, 0}, 0.5)
ball:set_material(glass)
floor = gr.cube('floor')
floor:translate(0, -1, 0)
floor:scale(4, 1, 4)
floor:set_material(gr.material({1, 1, 1}, {0, 0, 0}, 0))
root = gr.node('root')
root:add_child(floor)
root:add_child(ball)
gr.render(root, 'focus.png', 32, 32, {0, 5, 0.01}, {0, -1, 0}, {0, 0, -1}, 24, {0, 0, 0},
          {gr.light({0.3, 4, 0.1}, {1, 1, 1}, {0, 0, 0.1})})
)";

/// The options of every accumulation below: only --passes and --resume change.
const std::string progressive = "render --integrator progressive --reproducible --adaptive-radius on "
                                "--caustic-num-photons 3000 ";

std::string file_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

// docs/OUTPUT.md, "Resuming an accumulation": 5 passes saved, then continued to 10, give the bits
// of 10 passes at once (the radius adaptation before pass 8 included); the state is kept beside
// the image.
TEST_F(Cli, ResumeContinuesASavedAccumulationToTheBitsOfOneRun) {
    write("focus.lua", focus_scene);
    ASSERT_EQ(run(progressive + "--passes 10 focus.lua -o whole.pfm").code, 0);
    EXPECT_FALSE(exists("whole.pfm.caustica-state"));  // only --resume saves
    const Result first = run(progressive + "--passes 5 --resume focus.lua -o part.pfm");
    ASSERT_EQ(first.code, 0) << first.output;
    ASSERT_TRUE(exists("part.pfm.caustica-state"));
    EXPECT_NE(file_bytes(dir_ / "part.pfm"), file_bytes(dir_ / "whole.pfm"));
    const Result second = run(progressive + "--passes 10 --resume focus.lua -o part.pfm");
    ASSERT_EQ(second.code, 0) << second.output;
    EXPECT_NE(second.output.find("continuing the accumulation in part.pfm.caustica-state (5 passes)"), std::string::npos)
        << second.output;
    EXPECT_EQ(file_bytes(dir_ / "part.pfm"), file_bytes(dir_ / "whole.pfm"));
}

TEST_F(Cli, ResumeRefusesAnotherJobsStateAndKeepsIt) {
    write("focus.lua", focus_scene);
    ASSERT_EQ(run(progressive + "--passes 3 --resume focus.lua -o part.pfm").code, 0);
    const std::string image = file_bytes(dir_ / "part.pfm"), state = file_bytes(dir_ / "part.pfm.caustica-state");
    const Result photons = run(progressive + "--passes 6 --caustic-num-photons 4000 --resume focus.lua -o part.pfm");
    EXPECT_EQ(photons.code, 2);
    EXPECT_NE(photons.output.find("part.pfm.caustica-state: cannot continue this accumulation: it was saved with other "
                                  "options"),
              std::string::npos)
        << photons.output;
    const Result per_pixel = run(progressive + "--passes 6 --photons-per-pixel 1 --resume focus.lua -o part.pfm");
    EXPECT_EQ(per_pixel.code, 2);
    EXPECT_NE(per_pixel.output.find("it was saved with other options"), std::string::npos) << per_pixel.output;
    const Result size = run(progressive + "--passes 6 --minres --resume focus.lua -o part.pfm");
    EXPECT_EQ(size.code, 2);
    EXPECT_NE(size.output.find("it was saved for a 32 x 32 image, this render is 100 x 100"), std::string::npos)
        << size.output;
    EXPECT_EQ(file_bytes(dir_ / "part.pfm"), image);
    EXPECT_EQ(file_bytes(dir_ / "part.pfm.caustica-state"), state);
    // A damaged state is refused with its reason, not continued.
    fs::resize_file(dir_ / "part.pfm.caustica-state", state.size() - 100);
    const Result damaged = run(progressive + "--passes 6 --resume focus.lua -o part.pfm");
    EXPECT_EQ(damaged.code, 2);
    EXPECT_NE(damaged.output.find("(truncated)"), std::string::npos) << damaged.output;
    // A render that does not accumulate has nothing to resume.
    const Result classic = run("render -s --resume focus.lua -o classic.pfm");
    EXPECT_EQ(classic.code, 2);
    EXPECT_NE(classic.output.find("does not accumulate passes"), std::string::npos) << classic.output;
}

TEST_F(Cli, CtrlCWithResumeSavesTheAccumulationForTheNextRun) {
    write("focus.lua", focus_scene);
    const std::string binary = CAUSTICA_BINARY;
    const std::string scene_path = (dir_ / "focus.lua").string(), out_path = (dir_ / "long.pfm").string();
    const char* argv[] = {binary.c_str(), "render", "--integrator", "progressive", "--caustic-num-photons", "3000",
                          "--time", "600", "--resume", scene_path.c_str(), "-o", out_path.c_str(), nullptr};
    pid_t pid;
    ASSERT_EQ(::posix_spawn(&pid, binary.c_str(), nullptr, nullptr, const_cast<char**>(argv), environ), 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // well into the passes
    ::kill(pid, SIGINT);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 130);
    EXPECT_FALSE(exists("long.pfm"));
    ASSERT_TRUE(exists("long.pfm.caustica-state"));
    // The next run continues it (to 2 passes: most likely no more than it holds, so it writes the
    // saved image).
    const Result next = run("render --integrator progressive --caustic-num-photons 3000 --passes 2 --resume focus.lua "
                            "-o long.pfm");
    EXPECT_EQ(next.code, 0) << next.output;
    EXPECT_NE(next.output.find("continuing the accumulation in long.pfm.caustica-state ("), std::string::npos)
        << next.output;
    EXPECT_TRUE(exists("long.pfm"));
}
