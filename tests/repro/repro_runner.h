// Runs `caustica` as a child process under hard limits, for the reproducer tests
// (tests/repro/test_repro*.cpp, docs/RELIABILITY.md): a regression fails fast instead of eating the
// machine.
//
// Each run forks, puts the child in its own process group (Ctrl-C is sent to the group, as a
// terminal does), sets RLIMIT_AS (not under AddressSanitizer, whose shadow memory needs terabytes
// of address space), RLIMIT_CPU and RLIMIT_CORE, and execs the binary in the test's folder. The
// parent polls: it collects stdout and stderr, samples the resident size and kills the whole group
// at the wall-clock or resident-size limit. The peak resident size comes from wait4 (exact).
#pragma once

#include "tests/time_bounds.h"

#include <sys/types.h>

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace caustica::repro {

namespace fs = std::filesystem;

inline constexpr std::size_t mib = std::size_t(1) << 20;
inline constexpr std::size_t gib = std::size_t(1) << 30;

/// True when this build runs under AddressSanitizer (no RLIMIT_AS, slower, more memory).
bool sanitized_build();

/// Factor on time bounds, wall clock and CPU time alike: the suite's one factor.
using caustica::testing::time_factor;

/// Factor on when a test acts (sends Ctrl-C, rewrites a scene) and on the script time limits it
/// sets: 1, or 4 under a sanitizer. Smaller than time_factor(): acting too late would miss the
/// stage under test, and larger limits would only make the suite slower.
double pace_factor();

/// A resident-size bound for a child that needs `bytes` in a plain build; under a sanitizer, four
/// times that plus 1 GiB (shadow memory, redzones around small allocations, the quarantine of freed
/// memory): loose, but a runaway still fails.
std::size_t rss_bound(std::size_t bytes);

/// Hard limits of one child. The test's own, tighter expectations are asserted on the Outcome.
struct Limits {
    double wall_seconds = 20.0;         ///< killed (SIGKILL to its group) after this long
    double cpu_seconds = 60.0;          ///< RLIMIT_CPU (SIGXCPU)
    std::size_t address_space = 4 * gib;  ///< RLIMIT_AS; ignored under a sanitizer
    std::size_t resident = 3 * gib;     ///< killed when VmRSS exceeds this (sampled every few ms)
};

/// What a child did.
struct Outcome {
    int exit_code = -1;       ///< -1 when it ended by a signal
    int signal = 0;           ///< the terminating signal, or 0
    std::string out;          ///< standard output (first and last 256 KiB)
    std::string err;          ///< standard error (first and last 256 KiB)
    double seconds = 0.0;     ///< wall-clock time from start to exit
    std::size_t peak_rss = 0; ///< peak resident size in bytes (getrusage of the child)
    std::string killed;       ///< why the runner killed it ("" when it ended by itself)
    bool stragglers = false;  ///< processes of its group still alive after it ended (then killed)

    /// One line for failure messages: code, signal, time, memory, stderr.
    std::string describe() const;
};

/// Called every few milliseconds while the child runs, with the elapsed seconds, its pid (also its
/// process group) and what it has written to stderr so far.
using Tick = std::function<void(double elapsed, pid_t child, const std::string& err)>;

/// One run of a program.
struct Launch {
    fs::path cwd;                                             ///< the folder it runs in
    std::vector<std::string> args;                            ///< arguments after the program
    std::vector<std::pair<std::string, std::string>> env;     ///< added to (or replacing in) the environment
    Limits limits;
    Tick tick;                                                ///< optional
    std::string program;                                      ///< "" for caustica_binary()
};

/// The caustica under test: $CAUSTICA_REPRO_BINARY when set (to check that the tests fail on an
/// older build), else the one built beside the tests.
std::string caustica_binary();

/// Runs `run` to its end (or the runner's kill) and reports what happened.
Outcome run_child(const Launch& run);

/// Sends `signal` to the child's process group, as a terminal does for Ctrl-C.
void signal_group(pid_t child, int signal);

/// Path of a file under tests/repro/ in the source tree.
fs::path repro_source(const std::string& relative);

/// Path of a file under fuzz/regressions/ in the source tree, e.g.
/// "scene_loader/repro_eye_far_minimal.lua": the reproducers that are also fuzz regressions are
/// kept there only (tests/repro/README.md).
fs::path regression_source(const std::string& relative);

/// The files of a folder tree (relative path -> size and modification time), symlinks not
/// followed: compared before and after a run to see what it wrote.
using Tree = std::map<std::string, std::pair<std::uintmax_t, long long>>;
Tree snapshot(const fs::path& root);

/// "+new", "~changed", "-removed" entries between two snapshots, sorted.
std::vector<std::string> changes(const Tree& before, const Tree& after);

/// A fresh folder per test under the system temporary folder, removed at the end.
class Scratch {
public:
    Scratch();
    ~Scratch();
    Scratch(const Scratch&) = delete;
    Scratch& operator=(const Scratch&) = delete;

    const fs::path& root() const { return root_; }
    /// Writes `text` to root()/relative (folders created).
    fs::path write(const std::string& relative, const std::string& text) const;
    /// Copies tests/repro/`from` to root()/`to`.
    fs::path copy(const std::string& from, const std::string& to) const;
    /// Copies the file `source` (a full path, e.g. a regression_source) to root()/`to`.
    fs::path copy_path(const fs::path& source, const std::string& to) const;

private:
    fs::path root_;
};

/// The text of a file.
std::string read_text(const fs::path& path);

/// True when `text` contains "<file>:<line>: " at the start of a line or after "caustica: " (or
/// "caustica view: "): the scene location of an error message.
bool names_location(const std::string& text, const std::string& file, int line);

// ---- what the tests share ----

/// RLIMIT_AS for a child whose memory use is what the test checks: far above its resident bound,
/// so that a regression shows as resident size (and is killed at the bound) instead of being
/// turned by RLIMIT_AS into a tidy "out of memory" error that would pass.
inline constexpr std::size_t roomy_address_space = 8 * gib;

/// Runs `caustica ARGS` (render or view) in `cwd`, killed past `wall_seconds` x time_factor() or
/// rss_bound(`resident`) bytes.
Outcome caustica_run(const fs::path& cwd, std::vector<std::string> args, double wall_seconds,
                     std::size_t resident = 1 * gib, std::vector<std::pair<std::string, std::string>> env = {},
                     std::size_t address_space = 4 * gib);

/// True when `text` contains `word`, ignoring case.
bool mentions(const std::string& text, std::string word);

/// GoogleTest expectations: exit 2 with the message at `file`:`line`, no process left behind.
void expect_scene_error(const Outcome& o, const std::string& file, int line);

/// The outcome a reproducer must end in: an image (line 0), or exit 2 with "file:line: call:".
struct Expected {
    int line = 0;      ///< the line of the offending call in the scene, 0 for an image
    std::string call;  ///< e.g. "gr.render"

    static Expected image() { return {}; }
    static Expected error(int line, std::string call) { return {line, std::move(call)}; }
};

/// GoogleTest expectations: `expected` happened (a complete `output` of width x height, or the
/// error with nothing written at `output`), and never a signal.
void expect_outcome(const Outcome& o, const fs::path& output, int width, int height, const std::string& file,
                    const Expected& expected);

}  // namespace caustica::repro
