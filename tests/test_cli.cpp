// The command line as a user meets it: exit codes, messages naming file:line, no partial output,
// Ctrl-C, precedence of the command line over gr.option, PNG metadata.
#include "core/png_io.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
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
        const std::string command = "cd '" + dir_.string() + "' && '" CAUSTICA_BINARY "' " + args + " 2>&1";
        Result r;
        FILE* pipe = ::popen(command.c_str(), "r");
        char buffer[4096];
        std::size_t n;
        while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
        const int status = ::pclose(pipe);
        r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        return r;
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
    EXPECT_EQ(run("--help").code, 0);
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

TEST_F(Cli, UnwritableOutputFolderIsRefusedBeforeRendering) {
    std::string scene = small_scene;
    scene.replace(scene.find("'out.png'"), 9, "'nodir/out.png'");
    write("scene.lua", scene);
    const Result r = run("render scene.lua");
    EXPECT_EQ(r.code, 2);
    EXPECT_NE(r.output.find("scene.lua:7: gr.render: cannot write 'nodir/out.png'"), std::string::npos) << r.output;
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
    EXPECT_LT(seconds, 1.0);
    EXPECT_TRUE(pngs().empty());
}
