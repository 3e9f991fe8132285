// `caustica render` under mpirun (docs/SCALING.md), real processes on this machine: K ranks make one
// process's image bit for bit (both integrators, --reproducible), share whole frames of an
// animation, stop together with the failing rank's message (a rank given another command than
// `render` included), and stop together on Ctrl-C with nothing written. Skipped, saying why, where
// caustica was built without MPI.
#include "tests/exr_channels.h"
#include "tests/run_command.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

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

std::string file_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

/// mpirun started in the background by /bin/sh, its output going to a log file.
class Background {
public:
    Background(const std::string& command, fs::path log) : log_(std::move(log)) {
        const std::string line = command + " > '" + log_.string() + "' 2>&1";
        const char* argv[] = {"/bin/sh", "-c", line.c_str(), nullptr};
        if (::posix_spawn(&pid_, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ) != 0) pid_ = 0;
    }
    ~Background() {
        if (pid_ > 0 && !ended_) {
            ::kill(pid_, SIGKILL);
            ::waitpid(pid_, &status_, 0);
        }
    }
    pid_t pid() const { return pid_; }
    std::string output() const { return file_text(log_); }
    bool says(const std::string& text) const { return output().find(text) != std::string::npos; }

    /// Polls every `step` until `ready` or `limit` seconds passed; whether it got ready.
    template <typename Ready>
    static bool poll(double limit, std::chrono::milliseconds step, Ready&& ready) {
        const auto t0 = std::chrono::steady_clock::now();
        while (std::chrono::steady_clock::now() - t0 < std::chrono::duration<double>(limit)) {
            if (ready()) return true;
            std::this_thread::sleep_for(step);
        }
        return false;
    }
    /// Waits up to `limit` seconds for the process to end, calling `tick` every 10 ms meanwhile;
    /// kills it when it does not end. Whether it ended by itself.
    template <typename Tick>
    bool wait(double limit, Tick&& tick) {
        ended_ = poll(limit, std::chrono::milliseconds(10), [&] {
            tick();
            return ::waitpid(pid_, &status_, WNOHANG) == pid_;
        });
        return ended_;
    }
    bool ended_with_success() const { return exit_code() == 0; }
    /// The exit code once it ended by itself; -1 before, or when a signal ended it.
    int exit_code() const { return ended_ && WIFEXITED(status_) ? WEXITSTATUS(status_) : -1; }

private:
    fs::path log_;
    pid_t pid_ = 0;
    int status_ = 0;
    bool ended_ = false;
};

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

    std::string read(const std::string& name) const { return file_text(dir_ / name); }

    /// `caustica render ARGS` on two ranks in the background, its output in log.txt.
    Background start(const std::string& args) const {
        return Background("cd '" + dir_.string() + "' && " + environment() + "exec " + launcher(2) + " '" + binary +
                              "' render " + args,
                          dir_ / "log.txt");
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

TEST_F(Mpi, PhotonsPerPixelRaiseTheSameCountOnEveryRank) {
    // Each rank raises its passes' photons from its own copy of the first pass's projection maps:
    // the same count, so the same bits as one process.
    // The peer ring: its light's map lets 0.8% of the directions through, so the count is raised.
    const std::string args = "'" CAUSTICA_SOURCE_DIR "/bench/peers/ring.lua' --reproducible --lores "
                             "--caustic-num-photons 2000 --photons-per-pixel 1 --integrator progressive --passes 4";
    const CommandResult alone = render(args + " -o alone.pfm", 0);
    ASSERT_EQ(alone.code, 0) << alone.output;
    const CommandResult shared = render(args + " -o shared.pfm", 2);
    ASSERT_EQ(shared.code, 0) << shared.output;
    EXPECT_EQ(read("shared.pfm"), read("alone.pfm"));
    // The option did raise the count: without it the image is another.
    const CommandResult given = render(std::string(args).replace(args.find("--photons-per-pixel 1 "), 22, "") +
                                       " -o given.pfm", 0);
    ASSERT_EQ(given.code, 0) << given.output;
    EXPECT_NE(read("given.pfm"), read("alone.pfm"));
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

TEST_F(Mpi, LayersComeBackWithTheTilesAsOneProcesssLayers) {
    // One image pass with anti-aliasing: the layers' first pass goes to every rank with the image's.
    const std::string args = "'" + box + "' --reproducible --lores --caustic-num-photons 100000 --layers --exr-pixel float";
    const CommandResult alone = render(args + " -o alone.exr", 0);
    ASSERT_EQ(alone.code, 0) << alone.output;
    const CommandResult shared = render(args + " -o shared.exr", 2);
    ASSERT_EQ(shared.code, 0) << shared.output;
    const auto one = caustica::testing::read_exr_channels((dir_ / "alone.exr").string()),
               two = caustica::testing::read_exr_channels((dir_ / "shared.exr").string());
    EXPECT_EQ(one.size(), 22u);
    EXPECT_TRUE(one == two) << "two processes' layers differ from one's";
    float brightest_caustic = 0.0f;
    for (float v : one.at("caustic.G")) brightest_caustic = std::max(brightest_caustic, v);
    EXPECT_GT(brightest_caustic, 0.0f);
    // An accumulation's layers, and whole frames', are refused before anything renders.
    for (const std::string refused : {" --integrator progressive --passes 3 -o acc.exr", " --orbit-frames 3 -o f.exr"}) {
        const CommandResult r = render(args + refused, 2);
        EXPECT_EQ(r.code, 2) << r.output;
        EXPECT_NE(r.output.find("--layers under mpirun"), std::string::npos) << r.output;
    }
    EXPECT_FALSE(exists("acc.exr"));
    EXPECT_FALSE(exists("f-0001.exr"));
}

TEST_F(Mpi, ResumeIsRefusedUnderMpirunBeforeAnyRendering) {
    // The ranks add their sums up only at the end of a frame (docs/OUTPUT.md, "Resuming an
    // accumulation"): refused once, by rank 0, nothing written.
    const CommandResult r = render("'" + box + "' --minres --integrator progressive --passes 4 --resume -o out.pfm", 2);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("caustica: --resume works in a single process, not under mpirun"), std::string::npos)
        << r.output;
    EXPECT_FALSE(exists("out.pfm"));
    EXPECT_FALSE(exists("out.pfm.caustica-state"));
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

TEST_F(Mpi, ARankGivenAnotherCommandStopsEveryRankNamingIt) {
    // mpirun's MPMD form: rank 0 renders, rank 1 is given a command that ends without rendering
    // (tests/repro/mpi/rank_version_hang.lua: --version; then --help, a misspelt command). Every
    // rank compares its command first: each run ends within seconds, exit 2, rank 0 naming rank 1
    // and both commands, nothing written. Without the comparison rank 0 waits for rank 1 for ever.
    fs::copy_file(CAUSTICA_SOURCE_DIR "/tests/repro/mpi/rank_version_hang.lua", dir_ / "a.lua");
    const std::string root = ::geteuid() == 0 ? " --allow-run-as-root" : "";
    const std::string rendering = "'" + binary + "' render a.lua -o x.png";
    for (const std::string other : {"--version", "--help", "rendre a.lua"}) {
        Background run("cd '" + dir_.string() + "' && " + environment() + "exec '" + mpirun + "'" + root + " -n 1 " +
                           rendering + " : -n 1 '" + binary + "' " + other,
                       dir_ / "log.txt");
        ASSERT_GT(run.pid(), 0);
        ASSERT_TRUE(run.wait(caustica::testing::time_bound(10.0), [] {}))
            << "rank 1 given '" << other << "': still running after 10 s\n" << run.output();
        const std::string output = run.output();
        EXPECT_EQ(run.exit_code(), 2) << output;
        EXPECT_NE(output.find("caustica: rank 1 of 2 was given 'caustica " + other +
                              "', where rank 0 was given 'caustica render a.lua -o x.png'"),
                  std::string::npos)
            << output;
        EXPECT_FALSE(exists("x.png")) << output;
    }
    // The same command on every rank still renders, and rank 0 writes.
    const CommandResult same = render("a.lua -o x.png", 2);
    EXPECT_EQ(same.code, 0) << same.output;
    EXPECT_TRUE(exists("x.png")) << same.output;
}

TEST_F(Mpi, ACtrlCStopsEveryRankAndWritesNothing) {
    // A progressive render of a thousand passes; mpirun gets SIGINT after a second, as from a
    // terminal, and passes it on. Every process ends within seconds, nothing is written.
    Background run = start("'" + box + "' -v --lores --integrator progressive --passes 1000 -o ctrl-c.pfm");
    ASSERT_GT(run.pid(), 0);
    // Wait until rank 0 renders (its -v line), then a little: the signal arrives mid-render.
    Background::poll(30.0, std::chrono::milliseconds(50), [&] { return run.says("rendering ctrl-c.pfm"); });
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::kill(run.pid(), SIGINT);
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(run.wait(30.0, [] {})) << "mpirun did not end within 30 s of Ctrl-C";
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const std::string output = run.output();
    EXPECT_FALSE(run.ended_with_success()) << output;
    EXPECT_FALSE(exists("ctrl-c.pfm")) << output;
    EXPECT_NE(output.find("interrupted"), std::string::npos) << output;
    EXPECT_LT(seconds, caustica::testing::time_bound(10.0)) << output;
    // No rank is left running.
    const CommandResult left = run_shell("pgrep -f 'render.*ctrl-c[.]pfm' || true");
    EXPECT_TRUE(left.output.empty()) << left.output;
}

TEST_F(Mpi, AnInterruptedWorkerStopsTheTileHandOutAtOnce) {
    // SIGTERM to rank 1 alone while the classic tiles are handed out: rank 0 stops handing out
    // and rendering batches, so every rank ends well before the render would have (without
    // stopping, rank 0 renders the rest of the tiles alone), and nothing is written.
    const std::string args = "'" CAUSTICA_SOURCE_DIR "/scenes/default.lua' -v --hires --caustic-num-photons 100000 "
                             "--caustic-num-neighbours 100";
    // The time bound is checked in the plain build only (under the sanitizers everything is
    // slower in ways no bound survives; the run still checks what ends and what is written).
    const bool timed = !std::getenv("ASAN_OPTIONS") && !std::getenv("TSAN_OPTIONS");
    double whole = 0.0;
    if (timed) {
        const auto whole_start = std::chrono::steady_clock::now();
        ASSERT_EQ(render(args + " -o whole.pfm", 2).code, 0);
        whole = std::chrono::duration<double>(std::chrono::steady_clock::now() - whole_start).count();
    }
    Background run = start(args + " -o sigterm.pfm");
    ASSERT_GT(run.pid(), 0);
    // Rank 1: the child of mpirun whose environment says so, once rank 0 renders (its -v line).
    pid_t rank1 = 0;
    Background::poll(30.0, std::chrono::milliseconds(50), [&] {
        if (!run.says("rendering sigterm.pfm")) return false;
        std::istringstream pids(run_shell("pgrep -P " + std::to_string(run.pid())).output);
        for (pid_t child; pids >> child;)
            if (file_text("/proc/" + std::to_string(child) + "/environ").find(std::string("OMPI_COMM_WORLD_RANK=1") + '\0') !=
                std::string::npos)
                rank1 = child;
        return rank1 != 0;
    });
    ASSERT_NE(rank1, 0) << "rank 1 not found";
    std::this_thread::sleep_for(std::chrono::milliseconds(500));  // into the tiles
    ::kill(rank1, SIGTERM);
    const auto t0 = std::chrono::steady_clock::now();
    auto since = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    double said = -1.0;  // when rank 0 said it stopped (mpirun itself then takes ~2 s to end)
    ASSERT_TRUE(run.wait(60.0, [&] {
        if (said < 0.0 && run.says("caustica: interrupted")) said = since();
    }));
    const double seconds = since();
    const std::string output = run.output();
    EXPECT_FALSE(run.ended_with_success()) << output;
    EXPECT_FALSE(exists("sigterm.pfm")) << output;
    EXPECT_NE(output.find("interrupted"), std::string::npos) << output;
    // Signalled about a second into a render of `whole` seconds: rank 0 stops after the batch in
    // hand and the agreement (0.06 s here). Without that it would render the rest of the tiles
    // alone, longer than half the whole render.
    std::printf("rank 0 stopped %.2f s after the signal, mpirun ended after %.2f s; a whole render takes %.2f s\n",
                said, seconds, whole);
    EXPECT_GE(said, 0.0) << output;
    if (timed) {
        EXPECT_LT(said, 0.3 * whole) << output;
    }
}
