// The reproducers of the hardening audit (tests/repro/README.md), part 1: the sandbox (S1, S2, S4,
// S5), bounded time (S3: long C calls, finalizers, one Ctrl-C; I1: one Ctrl-C inside a long packet)
// and atomic output under signals (A1). Each test runs `caustica render` in a child under hard limits (tests/repro/repro_runner.h)
// on a copy of the reproducer in a fresh folder, and asserts the exact outcome: exit code, the
// "file:line:" of the message, nothing read or written outside, the time taken. Part 2 (memory,
// crashes, NaN) is test_repro_resources.cpp, part 3 (OBJ, PNG) test_repro_inputs.cpp, part 4 (outputs
// through symlinks) test_repro_output.cpp.
#include "tests/repro/repro_runner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <fstream>
#include <functional>
#include <sys/stat.h>
#include <unistd.h>

using namespace caustica::repro;

namespace {

/// Seconds a stopped script may take past --script-timeout (the watchdog's grace) before the test
/// calls it a failure.
double grace() { return 2.0 * time_factor(); }

/// Runs `caustica render ARGS` in `cwd`, killed after `wall_seconds` (scaled).
Outcome render(const fs::path& cwd, std::vector<std::string> args, double wall_seconds = 10.0,
               std::vector<std::pair<std::string, std::string>> env = {}) {
    args.insert(args.begin(), "render");
    return caustica_run(cwd, std::move(args), wall_seconds, 1 * gib, std::move(env));
}

/// The script was stopped by --script-timeout `timeout` (seconds): exit 2 within the grace, the
/// message names the line of the long call.
void expect_stopped_by_timeout(const Outcome& o, const std::string& file, int line, double timeout) {
    expect_scene_error(o, file, line);
    const std::string stopped = file + ":" + std::to_string(line) + ": script stopped after ";
    EXPECT_NE(o.err.find(stopped), std::string::npos) << "expected '" << stopped << "'\n" << o.describe();
    EXPECT_NE(o.err.find("(--script-timeout)"), std::string::npos) << o.describe();
    EXPECT_GE(o.seconds, 0.9 * timeout) << o.describe();
    EXPECT_LE(o.seconds, timeout + grace()) << o.describe();
    EXPECT_FALSE(o.stragglers) << o.describe();
}

/// Interrupted by one SIGINT sent at `sent_at`: exit 130 within a second of it.
void expect_interrupted(const Outcome& o, double sent_at) {
    EXPECT_EQ(o.exit_code, 130) << o.describe();
    ASSERT_GT(sent_at, 0.0) << "the SIGINT was never sent\n" << o.describe();
    EXPECT_LE(o.seconds - sent_at, 1.0 * time_factor()) << "SIGINT sent at " << sent_at << " s\n" << o.describe();
    EXPECT_FALSE(o.stragglers) << o.describe();
}

/// Nothing in the folder tree changed.
void expect_unchanged(const Tree& before, const fs::path& root, const Outcome& o) {
    EXPECT_EQ(changes(before, snapshot(root)), std::vector<std::string>{}) << o.describe();
}

/// A tick that sends one SIGINT to the child's group at `at` seconds and records when.
Tick interrupt_at(double at, double& sent_at) {
    return [at, &sent_at](double t, pid_t child, const std::string&) {
        if (sent_at == 0.0 && t >= at) {
            signal_group(child, SIGINT);
            sent_at = t;
        }
    };
}

/// Runs `caustica render -v SCENE -o x.png` in `cwd` (killed past `wall_seconds`, scaled) and
/// sends one SIGINT `delay` seconds after the line "SCENE:LINE: rendering" (the script has run):
/// exit 130 within a second of the signal, x.png not written.
Outcome expect_ctrl_c_after_loading(const fs::path& cwd, const std::string& scene, int line, double delay,
                                    double wall_seconds) {
    Launch run;
    run.cwd = cwd;
    run.args = {"render", "-v", scene, "-o", "x.png"};
    run.limits.wall_seconds = wall_seconds * time_factor();
    const std::string marker = scene + ":" + std::to_string(line) + ": rendering";
    double loaded_at = 0.0, sent_at = 0.0;
    run.tick = [&](double t, pid_t child, const std::string& err) {
        if (loaded_at == 0.0 && err.find(marker) != std::string::npos) loaded_at = t;
        if (loaded_at > 0.0 && sent_at == 0.0 && t >= loaded_at + delay) {
            signal_group(child, SIGINT);
            sent_at = t;
        }
    };
    const Outcome o = run_child(run);
    expect_interrupted(o, sent_at);
    EXPECT_FALSE(fs::exists(cwd / "x.png"));
    return o;
}

}  // namespace

// ---- S1: no binary chunk reaches the Lua VM ----

TEST(ReproRunner, AProcessLeftRunningInTheGroupIsAStragglerAnEndedOneIsNot) {
    // The runner's check behind every "no stragglers" expectation: a child left sleeping after its
    // parent exits is one; a child that ended before it (and was reaped, or is a zombie) is not.
    Scratch s;
    Launch left;
    left.cwd = s.root();
    left.program = "/bin/sh";
    left.args = {"-c", "sleep 30 & exit 0"};
    const Outcome o = run_child(left);
    EXPECT_EQ(o.exit_code, 0) << o.describe();
    EXPECT_TRUE(o.stragglers) << o.describe();
    EXPECT_LT(o.seconds, 10.0) << o.describe();

    Launch ended = left;
    ended.args = {"-c", "sleep 0 & wait; exit 0"};
    const Outcome e = run_child(ended);
    EXPECT_EQ(e.exit_code, 0) << e.describe();
    EXPECT_FALSE(e.stragglers) << e.describe();

    // A child that ended but was never reaped (the exec'd sleep does not wait for it) is a zombie
    // until init takes it: not running, so not a straggler.
    Launch unreaped = left;
    unreaped.args = {"-c", "sleep 0 & exec sleep 0.2"};
    const Outcome z = run_child(unreaped);
    EXPECT_EQ(z.exit_code, 0) << z.describe();
    EXPECT_FALSE(z.stragglers) << z.describe();
}

TEST(ReproSandbox, S1_UnwrappedLoadIsUnreachableThroughDebugGetinfo) {
    Scratch s;
    s.copy("sandbox_real_load/escape_load_binary.lua", "scene/escape_load_binary.lua");
    const Tree before = snapshot(s.root());
    const Outcome o = render(s.root() / "scene", {"escape_load_binary.lua", "-o", "x.png"});
    EXPECT_EQ(o.out.find("BINARY CHUNK LOADED"), std::string::npos) << o.describe();
    // debug.getinfo gives no function (the reader's error stays inside load): real_load is nil.
    expect_scene_error(o, "escape_load_binary.lua", 12);
    EXPECT_NE(o.err.find("(local 'real_load')"), std::string::npos) << o.describe();
    expect_unchanged(before, s.root(), o);
}

TEST(ReproSandbox, S1_CraftedBytecodeIsRefusedNotRun) {
    Scratch s;
    s.copy("sandbox_real_load/escape_bytecode_crash.lua", "scene/escape_bytecode_crash.lua");
    const Tree before = snapshot(s.root());
    const Outcome o = render(s.root() / "scene", {"escape_bytecode_crash.lua", "-o", "x.png"});
    EXPECT_EQ(o.signal, 0) << o.describe();
    expect_scene_error(o, "escape_bytecode_crash.lua", 4);  // real_load is nil
    EXPECT_NE(o.err.find("(local 'real_load')"), std::string::npos) << o.describe();
    EXPECT_EQ(o.out.find("got value"), std::string::npos) << o.describe();
    expect_unchanged(before, s.root(), o);
}

// ---- S2: reads follow symlinks with the real file system ----

TEST(ReproSandbox, S2_SymlinkOutOfTheFolderIsRefusedOnEveryRoute) {
    Scratch s;
    s.copy("sandbox_symlink_fallback/escape_symlink.lua", "scene/escape_symlink.lua");
    fs::create_symlink("/etc", s.root() / "scene/etclink");
    fs::create_symlink("loop", s.root() / "scene/loop");
    std::string first_line;
    std::getline(std::ifstream("/etc/passwd"), first_line);
    ASSERT_FALSE(first_line.empty());
    const Tree before = snapshot(s.root());
    const Outcome o = render(s.root() / "scene", {"escape_symlink.lua", "-o", "x.png"});
    EXPECT_EQ(o.out.find(first_line), std::string::npos) << o.describe();
    EXPECT_EQ(o.err.find(first_line), std::string::npos) << o.describe();
    EXPECT_EQ(o.out.find("OPENED"), std::string::npos) << o.describe();
    EXPECT_NE(o.out.find("symlink used directly: refused"), std::string::npos) << o.describe();
    EXPECT_NE(o.out.find("ENAMETOOLONG component, then ..: refused"), std::string::npos) << o.describe();
    EXPECT_NE(o.out.find("symlink loop, then ..: refused"), std::string::npos) << o.describe();
    expect_scene_error(o, "escape_symlink.lua", 9);  // io.lines raises
    EXPECT_NE(o.err.find("io.lines"), std::string::npos) << o.describe();
    expect_unchanged(before, s.root(), o);
}

// ---- S5: require does not follow a symlink out of the folder ----

TEST(ReproSandbox, S5_RequireThroughASymlinkIsRefused) {
    Scratch s;
    s.copy("sandbox_require_symlink/escape_require.lua", "scene/escape_require.lua");
    s.write("outside/outmod.lua", "return \"module from OUTSIDE the scene folder\"\n");
    fs::create_directory_symlink(s.root() / "outside", s.root() / "scene/include");
    fs::create_symlink("/etc/passwd", s.root() / "scene/pw.lua");
    std::string first_line;
    std::getline(std::ifstream("/etc/passwd"), first_line);
    const std::string first_token = first_line.substr(0, first_line.find(':'));
    const Tree before = snapshot(s.root());
    const Outcome o = render(s.root() / "scene", {"escape_require.lua", "-o", "x.png"});
    EXPECT_EQ(o.out.find("module from OUTSIDE"), std::string::npos) << o.describe();
    EXPECT_NE(o.out.find("require outmod: "), std::string::npos) << o.describe();  // pcall caught the refusal
    const std::size_t pw = o.out.find("require pw (-> /etc/passwd): ");
    ASSERT_NE(pw, std::string::npos) << o.describe();
    const std::string pw_line = o.out.substr(pw, o.out.find('\n', pw) - pw);
    EXPECT_EQ(pw_line.find(" near "), std::string::npos) << "the file was parsed: " << pw_line;
    EXPECT_EQ(pw_line.find("pw.lua:1:"), std::string::npos) << "the file was parsed: " << pw_line;
    if (!first_token.empty() && first_token != "pw") {
        EXPECT_EQ(pw_line.find(first_token), std::string::npos) << pw_line;
    }
    EXPECT_EQ(o.exit_code, 2) << o.describe();
    EXPECT_NE(o.err.find("escape_require.lua: the script calls no gr.render"), std::string::npos) << o.describe();
    expect_unchanged(before, s.root(), o);
}

// ---- S3: __gc on the shared metatables is refused (finalizers run with hooks off) ----

TEST(ReproSandbox, S3_GcOnTheFileHandleMetatableIsRefused) {
    Scratch s;
    s.copy("sandbox_gc_finalizer/escape_gc_filehandle.lua", "scene/escape_gc_filehandle.lua");
    const Outcome o = render(s.root() / "scene", {"--script-timeout", "2", "escape_gc_filehandle.lua", "-o", "x.png"});
    expect_scene_error(o, "escape_gc_filehandle.lua", 4);  // mt.__gc = ...: the metatable is protected
    EXPECT_NE(o.err.find("(local 'mt')"), std::string::npos) << o.describe();
    EXPECT_EQ(o.err.find("finalizer running"), std::string::npos) << o.describe();
    EXPECT_LE(o.seconds, 1.0 * time_factor()) << o.describe();
}

TEST(ReproSandbox, S3_GcOnTheHandleMetatableIsRefused) {
    Scratch s;
    s.copy("sandbox_gc_finalizer/escape_gc_handle.lua", "scene/escape_gc_handle.lua");
    const Outcome o = render(s.root() / "scene", {"--script-timeout", "2", "escape_gc_handle.lua", "-o", "x.png"});
    expect_scene_error(o, "escape_gc_handle.lua", 3);
    EXPECT_NE(o.err.find("(local 'mt')"), std::string::npos) << o.describe();
    EXPECT_EQ(o.err.find("finalizer running"), std::string::npos) << o.describe();
    EXPECT_LE(o.seconds, 1.0 * time_factor()) << o.describe();
}

// ---- S4: gr.render never writes outside the current folder ----

namespace {

/// scratch/scene (the current folder, with the script) and scratch/outside/victim.png.
struct OutputCase {
    Scratch s;
    fs::path victim = s.write("outside/victim.png", "VICTIM: must stay as it is");
    fs::path scene = s.copy("output_path_anywhere/escape_output_path.lua", "scene/escape_output_path.lua");
};

}  // namespace

TEST(ReproSandbox, S4_AbsoluteOutputNameIsRefused) {
    OutputCase c;
    const Tree before = snapshot(c.s.root());
    const Outcome o = render(c.s.root() / "scene", {"escape_output_path.lua"}, 10.0, {{"VICTIM", c.victim.string()}});
    expect_scene_error(o, "escape_output_path.lua", 6);
    EXPECT_NE(o.err.find("escape_output_path.lua:6: gr.render: "), std::string::npos) << o.describe();
    EXPECT_EQ(read_text(c.victim), "VICTIM: must stay as it is");
    expect_unchanged(before, c.s.root(), o);
}

TEST(ReproSandbox, S4_ClimbingOutputNameIsRefused) {
    OutputCase c;
    c.s.copy("output_path_anywhere/climb_output_path.lua", "scene/climb_output_path.lua");
    const Tree before = snapshot(c.s.root());
    const Outcome o = render(c.s.root() / "scene", {"climb_output_path.lua"});
    expect_scene_error(o, "climb_output_path.lua", 5);
    EXPECT_NE(o.err.find("climb_output_path.lua:5: gr.render: "), std::string::npos) << o.describe();
    expect_unchanged(before, c.s.root(), o);
}

TEST(ReproSandbox, S4_OutputFlagStillWins) {
    OutputCase c;
    const Tree before = snapshot(c.s.root());
    const Outcome o = render(c.s.root() / "scene", {"-s", "escape_output_path.lua", "-o", "out.png"}, 10.0,
                             {{"VICTIM", c.victim.string()}});
    EXPECT_EQ(o.exit_code, 0) << o.describe();
    EXPECT_EQ(changes(before, snapshot(c.s.root())), (std::vector<std::string>{"+scene/out-1.png", "+scene/out-2.png"}))
        << o.describe();
    EXPECT_EQ(read_text(c.victim), "VICTIM: must stay as it is");
}

// ---- M1: an output folder that cannot be written is exit 1, found before or after rendering ----

TEST(ReproSandbox, M1_MissingOutputFolderBeforeRenderingExits1) {
    Scratch s;
    std::string scene = read_text(repro_source("atomic/big.lua"));
    scene.replace(scene.find("'big.png'"), 9, "'nodir/big.png'");
    s.write("big.lua", scene);
    const Tree before = snapshot(s.root());
    const Outcome o = render(s.root(), {"-s", "big.lua"});
    EXPECT_EQ(o.exit_code, 1) << o.describe();
    EXPECT_NE(o.err.find("big.lua:4: gr.render: cannot write 'nodir/big.png'"), std::string::npos) << o.describe();
    EXPECT_LE(o.seconds, 1.0 * time_factor()) << o.describe();
    expect_unchanged(before, s.root(), o);
}

TEST(ReproSandbox, M1_OutputFolderRemovedWhileRenderingExits1) {
    Scratch s;
    s.copy("atomic/big.lua", "big.lua");
    fs::create_directories(s.root() / "out");
    Launch run;
    run.cwd = s.root();
    run.args = {"render", "-s", "--disable-aa", "big.lua", "-o", "out/big.png"};  // one sample a pixel: the write is what matters
    run.limits.wall_seconds = 20.0 * time_factor();
    bool removed = false;
    run.tick = [&](double t, pid_t, const std::string&) {
        std::error_code error;  // not yet if the write has begun in it: then the next tick
        if (!removed && t > 0.3 * pace_factor()) removed = fs::remove(s.root() / "out", error);
    };
    const Tree before = snapshot(s.root());
    const Outcome o = run_child(run);
    ASSERT_TRUE(removed);
    EXPECT_EQ(o.exit_code, 1) << o.describe();
    EXPECT_NE(o.err.find("out/big.png"), std::string::npos) << o.describe();
    EXPECT_EQ(changes(before, snapshot(s.root())), std::vector<std::string>{"-out"}) << o.describe();
}

// ---- S3: --script-timeout also stops long C calls; one Ctrl-C stops them ----

namespace {

/// Runs exhaustion/`name` with --script-timeout `timeout` and checks it stops in time, at `line`.
void expect_timeout_stops(const std::string& name, int line, double timeout) {
    Scratch s;
    s.copy("exhaustion/" + name, "scene/" + name);
    const Tree before = snapshot(s.root());
    char seconds[32];
    std::snprintf(seconds, sizeof seconds, "%g", timeout);
    const Outcome o = render(s.root() / "scene", {"--script-timeout", seconds, name, "-o", "x.png"},
                             (timeout + grace()) / time_factor() + 3.0);
    expect_stopped_by_timeout(o, name, line, timeout);
    expect_unchanged(before, s.root(), o);
}

}  // namespace

TEST(ReproTime, S3_InfiniteLoopStopsAtTheTimeout) {
    expect_timeout_stops("infinite_loop.lua", 1, 1.0 * pace_factor());
}

TEST(ReproTime, S3_PatternBacktrackingStopsAtTheTimeout) {
    expect_timeout_stops("pattern_backtrack.lua", 5, 1.0 * pace_factor());
}

TEST(ReproTime, S3_GsubBacktrackingStopsAtTheTimeout) {
    expect_timeout_stops("gsub_backtrack.lua", 2, 1.0 * pace_factor());
}

TEST(ReproTime, S3_TableMoveStopsAtTheTimeout) {
    expect_timeout_stops("table_move.lua", 3, 1.0 * pace_factor());
}

TEST(ReproTime, S3_LongTableSortStopsAtTheTimeout) {
    // The limit must fall inside table.sort (line 4), after the loop that fills the 3e7 entries:
    // about 1 s on some machines, nearly 4 on virtual machines whose page faults are slow (half a
    // gigabyte is touched), where the sort then takes ten times as long. So the filling is timed
    // first, alone (the reproducer's own lines up to the sort), and the limit set well past it.
    Scratch s;
    const std::string text = read_text(s.copy("exhaustion/sort_big.lua", "sort_big.lua"));
    const std::size_t sort_at = text.find("table.sort");
    ASSERT_NE(sort_at, std::string::npos);
    s.write("fill/fill.lua", text.substr(0, sort_at) + "error('filled')\n");
    const Outcome fill = render(s.root() / "fill", {"--script-timeout", "600", "fill.lua", "-o", "x.png"}, 600.0);
    ASSERT_TRUE(names_location(fill.err, "fill.lua", 4)) << fill.describe();
    expect_timeout_stops("sort_big.lua", 4, std::max(3.0 * pace_factor(), 1.5 * fill.seconds + 1.0));
}

TEST(ReproTime, S3_OneCtrlCStopsARunawayPattern) {
    Scratch s;
    s.copy("exhaustion/pattern_backtrack.lua", "scene/pattern_backtrack.lua");
    Launch run;
    run.cwd = s.root() / "scene";
    run.args = {"render", "pattern_backtrack.lua", "-o", "x.png"};
    run.limits.wall_seconds = 6.0 * time_factor();
    double sent_at = 0.0;
    run.tick = interrupt_at(1.0 * pace_factor(), sent_at);
    const Outcome o = run_child(run);
    expect_interrupted(o, sent_at);
    EXPECT_FALSE(fs::exists(run.cwd / "x.png"));
}

TEST(ReproTime, S3_OneCtrlCStopsTableMove) {
    Scratch s;
    s.copy("exhaustion/table_move.lua", "scene/table_move.lua");
    Launch run;
    run.cwd = s.root() / "scene";
    run.args = {"render", "table_move.lua", "-o", "x.png"};
    run.limits.wall_seconds = 6.0 * time_factor();
    double sent_at = 0.0;
    run.tick = interrupt_at(1.0 * pace_factor(), sent_at);
    const Outcome o = run_child(run);
    expect_interrupted(o, sent_at);
}

namespace {

/// A scene of one mesh of 2e6 vertices and faces (about 90 MB of OBJ): gr.mesh takes about 0.6 s,
/// building the scene for rendering (Embree BVH) about 3 s.
void write_big_mesh_scene(const Scratch& s) {
    std::ofstream obj(s.root() / "big.obj", std::ios::binary);
    std::string chunk;
    constexpr int n = 2'000'000;
    char line[96];
    for (int i = 0; i < n; ++i) {
        std::snprintf(line, sizeof line, "v %d.5 %d.25 %d.125\n", i % 1000, (i / 1000) % 1000, i % 7);
        chunk += line;
        if (chunk.size() > (1 << 20)) {
            obj << chunk;
            chunk.clear();
        }
    }
    for (int i = 1; i + 2 <= n; ++i) {
        std::snprintf(line, sizeof line, "f %d %d %d\n", i, i + 1, i + 2);
        chunk += line;
        if (chunk.size() > (1 << 20)) {
            obj << chunk;
            chunk.clear();
        }
    }
    obj << chunk;
    s.write("scene.lua",
            "local m = gr.mesh('m', 'big.obj')\n"
            "m:set_material(gr.material({0.8,0.6,0.2},{0,0,0},10))\n"
            "local l = gr.light({5,5,5},{1,1,1},{1,0,0})\n"
            "gr.render(m, 'x.png', 16, 16, {0.5,0.5,4}, {0,0,-1}, {0,1,0}, 50, {0.1,0.1,0.1}, {l})\n");
}

/// With -v, the line render_job prints once the script has run: "scene.lua:4: rendering x.png".
const char* rendering_marker = "scene.lua:4: rendering";

}  // namespace

TEST(ReproTime, S3_OneCtrlCStopsLoadingABigObj) {
    Scratch s;
    write_big_mesh_scene(s);
    Launch run;
    run.cwd = s.root();
    run.args = {"render", "-v", "scene.lua", "-o", "x.png"};
    run.limits.wall_seconds = 15.0 * time_factor();
    double sent_at = 0.0;
    bool still_loading = false;
    run.tick = [&](double t, pid_t child, const std::string& err) {
        if (sent_at == 0.0 && t >= 0.25 * pace_factor()) {
            still_loading = err.find(rendering_marker) == std::string::npos;
            signal_group(child, SIGINT);
            sent_at = t;
        }
    };
    const Outcome o = run_child(run);
    ASSERT_TRUE(still_loading) << "the OBJ was loaded before the Ctrl-C\n" << o.describe();
    expect_interrupted(o, sent_at);
    EXPECT_NE(o.err.find("interrupted while running scene.lua"), std::string::npos) << o.describe();
    EXPECT_FALSE(fs::exists(run.cwd / "x.png"));
}

TEST(ReproTime, S3_OneCtrlCStopsBuildingTheSceneOfABigMesh) {
    Scratch s;
    write_big_mesh_scene(s);
    expect_ctrl_c_after_loading(s.root(), "scene.lua", 4, 0.2, 15.0);  // into the Embree build
}

// ---- I1: one Ctrl-C stops a camera packet through 262 144 overlapping spheres ----

// The scene builds in under a second; its one tile takes seconds, each packet of 8 rays tens of
// milliseconds. The SIGINT comes inside the tile; nothing is written.
TEST(ReproTime, I1_OneCtrlCStopsACameraPacketAndWritesNothing) {
    Scratch s;
    s.copy("interrupt/overlapping_spheres.lua", "overlapping_spheres.lua");
    const Outcome o = expect_ctrl_c_after_loading(s.root(), "overlapping_spheres.lua", 14, 2.0 * pace_factor(), 30.0);
    EXPECT_NE(o.err.find("interrupted; x.png not written"), std::string::npos) << o.describe();
}

// ---- A1: a Ctrl-C during the PNG write stops it; nothing partial is ever at the output path ----

namespace {

/// atomic/big.lua (4096 x 4096: about 0.7 s of rendering, then about 0.7 s of PNG writing) with
/// -o out/out.png. `act` is called once when a new file appears in out/ (the temporary of the
/// write), with the elapsed seconds and the child's pid.
struct AtomicCase {
    Scratch s;
    fs::path out_dir = s.root() / "out";
    std::string before_text;  ///< what out/out.png held before, "" when absent

    explicit AtomicCase(const std::string& existing = "") : before_text(existing) {
        s.copy("atomic/big.lua", "big.lua");
        fs::create_directories(out_dir);
        if (!existing.empty()) s.write("out/out.png", existing);
    }

    Outcome run(const std::function<void(double, pid_t)>& act, bool& acted) {
        Launch run;
        run.cwd = s.root();
        run.args = {"render", "-s", "--disable-aa", "big.lua", "-o", (out_dir / "out.png").string()};  // the write is what matters
        run.limits.wall_seconds = 30.0 * time_factor();
        const Tree initial = snapshot(out_dir);
        run.tick = [&, initial](double t, pid_t child, const std::string&) {
            if (acted) return;
            for (const std::string& change : changes(initial, snapshot(out_dir)))
                if (change[0] == '+') {
                    act(t, child);
                    acted = true;
                    return;
                }
        };
        return run_child(run);
    }

    /// out/ holds exactly what it held before (no output, no temporary).
    void expect_untouched(const Outcome& o) const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(out_dir)) names.push_back(entry.path().filename().string());
        EXPECT_EQ(names, before_text.empty() ? std::vector<std::string>{} : std::vector<std::string>{"out.png"})
            << o.describe();
        if (!before_text.empty()) {
            EXPECT_EQ(read_text(out_dir / "out.png"), before_text);
        }
    }
};

}  // namespace

TEST(ReproAtomic, A1_OneCtrlCDuringThePngWrite) {
    AtomicCase c;
    bool acted = false;
    double sent_at = 0.0;
    const Outcome o = c.run(
        [&](double t, pid_t child) {
            signal_group(child, SIGINT);
            sent_at = t;
        },
        acted);
    ASSERT_TRUE(acted) << "no temporary file appeared in the output folder during the write\n" << o.describe();
    expect_interrupted(o, sent_at);
    c.expect_untouched(o);
}

TEST(ReproAtomic, A1_TwoCtrlCsDuringThePngWrite) {
    AtomicCase c;
    bool acted = false;
    const Outcome o = c.run(
        [](double, pid_t child) {
            signal_group(child, SIGINT);
            ::usleep(50'000);
            signal_group(child, SIGINT);
        },
        acted);
    ASSERT_TRUE(acted) << o.describe();
    EXPECT_EQ(o.exit_code, 130) << o.describe();
    c.expect_untouched(o);
}

TEST(ReproAtomic, A1_CtrlCDuringTheWriteKeepsTheOldOutput) {
    AtomicCase c("OLD CONTENT");
    bool acted = false;
    const Outcome o = c.run([](double, pid_t child) { signal_group(child, SIGINT); }, acted);
    ASSERT_TRUE(acted) << o.describe();
    EXPECT_EQ(o.exit_code, 130) << o.describe();
    c.expect_untouched(o);
}

TEST(ReproAtomic, A1_NextRunLeavesNoTemporaryOfAKilledWrite) {
    AtomicCase c;
    bool acted = false;
    const Outcome killed = c.run([](double, pid_t child) { signal_group(child, SIGKILL); }, acted);
    ASSERT_TRUE(acted) << killed.describe();
    EXPECT_EQ(killed.signal, SIGKILL) << killed.describe();
    EXPECT_FALSE(fs::exists(c.out_dir / "out.png")) << "a killed write left a file at the output path";
    bool never = false;
    const Outcome next = c.run([](double, pid_t) {}, never);
    EXPECT_EQ(next.exit_code, 0) << next.describe();
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(c.out_dir)) names.push_back(entry.path().filename().string());
    EXPECT_EQ(names, std::vector<std::string>{"out.png"}) << next.describe();
}
