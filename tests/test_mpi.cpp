// `caustica render` under mpirun (issue 13), real processes on this machine: K ranks make one
// process's image bit for bit (both integrators, --reproducible), share whole frames of an
// animation, stop together with the failing rank's message, and stop together on Ctrl-C with
// nothing written. Skipped, saying why, where caustica was built without MPI.
#include "run_command.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace fs = std::filesystem;
using caustica::testing::CommandResult;
using caustica::testing::run_shell;

namespace {

const std::string mpirun = CAUSTICA_MPIRUN;
const std::string binary = CAUSTICA_BINARY;
const std::string box = CAUSTICA_SOURCE_DIR "/tests/ui/scenes/caustic_box.lua";

class Mpi : public ::testing::Test {
protected:
    void SetUp() override {
        if (mpirun.empty())
            GTEST_SKIP() << "caustica was built without MPI (apt install openmpi-bin libopenmpi-dev, then configure again)";
        dir_ = fs::temp_directory_path() /
               ("caustica-mpi-" + std::to_string(::getpid()) + "-" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        if (!dir_.empty()) fs::remove_all(dir_);
    }

    /// Under AddressSanitizer (scripts/test.sh sets ASAN_OPTIONS) the ranks unwind allocations
    /// fully: what Open MPI's plugins allocate is then seen to come from Open MPI's libraries,
    /// which tests/lsan.supp names (the fast unwinder stops inside the plugins, unloaded by then).
    static std::string environment() {
        const char* asan = std::getenv("ASAN_OPTIONS");
        return asan ? "ASAN_OPTIONS='" + std::string(asan) + ":fast_unwind_on_malloc=0' " : "";
    }

    /// mpirun's own options: root needs the flag (CI runs as root); more ranks than cores need
    /// --oversubscribe.
    static std::string launcher(int ranks) {
        std::string l = "'" + mpirun + "' -n " + std::to_string(ranks);
        if (::geteuid() == 0) l += " --allow-run-as-root";
        if (ranks > 2) l += " --oversubscribe";
        return l;
    }

    CommandResult render(const std::string& args, int ranks) const {
        const std::string caustica = "'" + binary + "' render " + args;
        return run_shell("cd '" + dir_.string() + "' && " + (ranks > 0 ? environment() + launcher(ranks) + " " : "") + caustica);
    }

    std::string read(const std::string& name) const {
        std::ifstream in(dir_ / name, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), {}};
    }
    bool exists(const std::string& name) const { return fs::exists(dir_ / name); }

    fs::path dir_;
};

}  // namespace

TEST_F(Mpi, TwoAndThreeProcessesMakeOneProcesssImageForBothIntegrators) {
    for (const std::string integrator : {"classic", "progressive"}) {
        const std::string args = "'" + box + "' --reproducible --lores --caustic-num-photons 200000 --integrator " +
                                 integrator + (integrator == "progressive" ? " --passes 5" : "");
        const CommandResult alone = render(args + " -o alone.pfm", 0);
        ASSERT_EQ(alone.code, 0) << alone.output;
        for (int ranks : {2, 3}) {
            const std::string name = integrator + std::to_string(ranks) + ".pfm";
            const CommandResult shared = render(args + " -o " + name, ranks);
            ASSERT_EQ(shared.code, 0) << shared.output;
            // Rank 0 alone speaks: one line for the file written.
            std::size_t wrote = 0;
            for (std::size_t at = 0; (at = shared.output.find("wrote ", at)) != std::string::npos; ++at) ++wrote;
            EXPECT_EQ(wrote, 1u) << shared.output;
            EXPECT_EQ(read(name), read("alone.pfm")) << integrator << " on " << ranks << " processes";
        }
    }
}

TEST_F(Mpi, MoreFramesThanRanksAreSharedAsWholeFrames) {
    const std::string args = "'" + box + "' --reproducible --minres --caustic-num-photons 100000 --orbit-frames 3";
    ASSERT_EQ(render(args + " -o alone.pfm", 0).code, 0);
    const CommandResult shared = render(args + " -o shared.pfm", 2);
    ASSERT_EQ(shared.code, 0) << shared.output;
    for (const std::string frame : {"0001", "0002", "0003"}) {
        ASSERT_TRUE(exists("shared-" + frame + ".pfm")) << shared.output;
        EXPECT_EQ(read("shared-" + frame + ".pfm"), read("alone-" + frame + ".pfm")) << "frame " << frame;
    }
    EXPECT_NE(read("shared-0001.pfm"), read("shared-0002.pfm"));  // the camera did turn
}

TEST_F(Mpi, AnErrorOnOneRankStopsEveryRankWithThatRanksMessage) {
    // mpirun's MPMD form gives rank 1 its own command line. Rank 0 says what rank 1 found, every
    // rank exits 2, nothing is written. First an error of rank 1 alone (its output name), then a
    // rank that loaded another job than rank 0 (its photon count): caught before any rendering.
    const std::string root = ::geteuid() == 0 ? " --allow-run-as-root" : "";
    const std::string good = "'" + binary + "' render '" + box + "' --minres -o out.png";
    for (const std::string& rank1 : {"'" + binary + "' render '" + box + "' --minres -o out.txt",
                                     good + " --caustic-num-photons 123456"}) {
        const CommandResult r =
            run_shell("cd '" + dir_.string() + "' && " + environment() + "'" + mpirun + "'" + root + " -n 1 " + good +
                      " : -n 1 " + rank1);
        EXPECT_EQ(r.code, 2) << r.output;
        EXPECT_NE(r.output.find("caustica: rank 1 of 2: "), std::string::npos) << r.output;
        EXPECT_NE(r.output.find(rank1.find("out.txt") != std::string::npos ? "-o out.txt: the output must end in"
                                                                            : "differ from rank 0's"),
                  std::string::npos)
            << r.output;
        EXPECT_FALSE(exists("out.png"));
    }
}

TEST_F(Mpi, ACtrlCStopsEveryRankAndWritesNothing) {
    // A progressive render of a thousand passes; mpirun gets SIGINT after a second, as from a
    // terminal, and passes it on. Every process ends within seconds, nothing is written.
    const std::string log = (dir_ / "log.txt").string();
    const std::string command = "cd '" + dir_.string() + "' && " + environment() + "exec " + launcher(2) + " '" + binary + "' render '" +
                                box + "' -v --lores --integrator progressive --passes 1000 -o ctrl-c.pfm > '" + log + "' 2>&1";
    const char* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
    pid_t pid = 0;
    ASSERT_EQ(::posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ), 0);
    // Wait until rank 0 renders (its -v line), then a little: the signal arrives mid-render.
    for (int i = 0; i < 600; ++i) {
        std::ifstream in(log);
        const std::string text{std::istreambuf_iterator<char>(in), {}};
        if (text.find("rendering ctrl-c.pfm") != std::string::npos) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::kill(pid, SIGINT);
    int status = 0;
    const auto t0 = std::chrono::steady_clock::now();
    bool ended = false;
    while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(30)) {
        if (::waitpid(pid, &status, WNOHANG) == pid) {
            ended = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (!ended) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
    }
    ASSERT_TRUE(ended) << "mpirun did not end within 30 s of Ctrl-C";
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ifstream in(log);
    const std::string output{std::istreambuf_iterator<char>(in), {}};
    EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << output;
    EXPECT_FALSE(exists("ctrl-c.pfm")) << output;
    EXPECT_NE(output.find("interrupted"), std::string::npos) << output;
    EXPECT_LT(seconds, 10.0) << output;
    // No rank is left running.
    const CommandResult left = run_shell("pgrep -f 'render.*ctrl-c[.]pfm' || true");
    EXPECT_TRUE(left.output.empty()) << left.output;
}

TEST_F(Mpi, AnInterruptedWorkerStopsTheTileHandOutAtOnce) {
    // SIGTERM to rank 1 alone while the classic tiles are handed out: rank 0 stops handing out
    // and rendering batches, so every rank ends well before the render would have (without
    // stopping, rank 0 renders the rest of the tiles alone), and nothing is written.
    const std::string args = "' render '" CAUSTICA_SOURCE_DIR "/scenes/default.lua' -v --hires --caustic-num-photons 100000 --caustic-num-neighbours 100";
    // The time bound is checked in the plain build only (under the sanitizers everything is
    // slower in ways no bound survives; the run still checks what ends and what is written).
    const bool timed = !std::getenv("ASAN_OPTIONS") && !std::getenv("TSAN_OPTIONS");
    double whole = 0.0;
    if (timed) {
        const auto whole_start = std::chrono::steady_clock::now();
        ASSERT_EQ(render(args.substr(9) + " -o whole.pfm", 2).code, 0);
        whole = std::chrono::duration<double>(std::chrono::steady_clock::now() - whole_start).count();
    }
    const std::string log = (dir_ / "log.txt").string();
    const std::string command = "cd '" + dir_.string() + "' && " + environment() + "exec " + launcher(2) + " '" +
                                binary + args + " -o sigterm.pfm > '" + log + "' 2>&1";
    const char* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
    pid_t pid = 0;
    ASSERT_EQ(::posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ), 0);
    // Rank 1: the child of mpirun whose environment says so, once rank 0 renders (its -v line).
    pid_t rank1 = 0;
    for (int i = 0; i < 600 && rank1 == 0; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        std::ifstream in(log);
        const std::string text{std::istreambuf_iterator<char>(in), {}};
        if (text.find("rendering sigterm.pfm") == std::string::npos) continue;
        const CommandResult children = run_shell("pgrep -P " + std::to_string(pid));
        std::istringstream pids(children.output);
        for (pid_t child; pids >> child;) {
            std::ifstream environment_file("/proc/" + std::to_string(child) + "/environ", std::ios::binary);
            const std::string env{std::istreambuf_iterator<char>(environment_file), {}};
            if (env.find(std::string("OMPI_COMM_WORLD_RANK=1") + '\0') != std::string::npos) rank1 = child;
        }
    }
    ASSERT_NE(rank1, 0) << "rank 1 not found";
    std::this_thread::sleep_for(std::chrono::milliseconds(500));  // into the tiles
    ::kill(rank1, SIGTERM);
    const auto t0 = std::chrono::steady_clock::now();
    int status = 0;
    bool ended = false;
    double said = -1.0;  // when rank 0 said it stopped (mpirun itself then takes ~2 s to end)
    while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(60)) {
        if (said < 0.0) {
            std::ifstream in(log);
            const std::string text{std::istreambuf_iterator<char>(in), {}};
            if (text.find("caustica: interrupted") != std::string::npos)
                said = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        }
        if (::waitpid(pid, &status, WNOHANG) == pid) {
            ended = true;
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!ended) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
    }
    ASSERT_TRUE(ended);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::ifstream in(log);
    const std::string output{std::istreambuf_iterator<char>(in), {}};
    EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << output;
    EXPECT_FALSE(exists("sigterm.pfm")) << output;
    EXPECT_NE(output.find("interrupted"), std::string::npos) << output;
    // Signalled about a second into a render of `whole` seconds: rank 0 stops after the batch in
    // hand and the agreement (0.06 s here). Without that it would render the rest of the tiles
    // alone, longer than half the whole render.
    std::printf("rank 0 stopped %.2f s after the signal, mpirun ended after %.2f s; a whole render takes %.2f s\n",
                said, seconds, whole);
    EXPECT_GE(said, 0.0) << output;
    if (timed) EXPECT_LT(said, 0.3 * whole) << output;
}
