// The child-process runner of the reproducer tests: see repro_runner.h.
#include "repro_runner.h"

#include "core/io/png_io.h"
#include "core/util/sanitized.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <poll.h>
#include <sched.h>
#include <sstream>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

extern char** environ;

namespace caustica::repro {
namespace {

/// Bytes of each stream kept from the start and from the end.
constexpr std::size_t kept_bytes = 256 * 1024;

/// Keeps the first and the last kept_bytes of a stream.
struct Capture {
    std::string head;
    std::string tail;
    bool cut = false;

    void add(const char* data, std::size_t n) {
        const std::size_t to_head = std::min(n, kept_bytes - head.size());
        head.append(data, to_head);
        if (to_head == n) return;
        tail.append(data + to_head, n - to_head);
        if (tail.size() > 2 * kept_bytes) {
            tail.erase(0, tail.size() - kept_bytes);
            cut = true;
        }
    }
    std::string text() const {
        if (!cut && tail.size() <= kept_bytes) return head + tail;
        return head + "\n[...]\n" + tail.substr(tail.size() > kept_bytes ? tail.size() - kept_bytes : 0);
    }
};

/// Reads what is available on a non-blocking pipe; false once it is closed.
bool drain(int fd, Capture& capture) {
    char buffer[65536];
    for (;;) {
        const ssize_t n = ::read(fd, buffer, sizeof buffer);
        if (n > 0) {
            capture.add(buffer, static_cast<std::size_t>(n));
            continue;
        }
        if (n == 0) return false;
        return errno == EAGAIN || errno == EINTR;
    }
}

/// VmRSS of a live process in bytes, 0 when it cannot be read.
std::size_t resident_bytes(pid_t pid) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmRSS:", 0) == 0) return std::strtoull(line.c_str() + 6, nullptr, 10) * 1024;
    return 0;
}

void set_limit(int resource, rlim_t soft, rlim_t hard) {
    rlimit limit{soft, hard};
    ::setrlimit(resource, &limit);
}

/// The environment of the child: ours with `extra` added or replaced, as "NAME=value" strings.
std::vector<std::string> child_environment(const std::vector<std::pair<std::string, std::string>>& extra) {
    std::vector<std::string> result;
    for (char** e = environ; *e; ++e) {
        const std::string entry = *e;
        const std::string name = entry.substr(0, entry.find('='));
        bool replaced = false;
        for (const auto& [n, v] : extra) replaced |= n == name;
        if (!replaced) result.push_back(entry);
    }
    for (const auto& [name, value] : extra) result.push_back(name + "=" + value);
    return result;
}

/// Null-terminated pointers to the strings (which must outlive the result).
std::vector<char*> pointers(std::vector<std::string>& strings) {
    std::vector<char*> result;
    for (std::string& s : strings) result.push_back(s.data());
    result.push_back(nullptr);
    return result;
}

/// In the forked child: process group, limits, streams, folder, then exec. Only async-signal-safe
/// calls (the parent has threads). Never returns.
[[noreturn]] void become_child(const Launch& run, char** argv, char** envp, int out_fd, int err_fd) {
    ::setpgid(0, 0);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    struct sigaction default_action {};
    default_action.sa_handler = SIG_DFL;
    for (int s : {SIGINT, SIGTERM, SIGPIPE, SIGXCPU}) ::sigaction(s, &default_action, nullptr);
    if (!caustica::sanitized_build && run.limits.address_space > 0)
        set_limit(RLIMIT_AS, run.limits.address_space, run.limits.address_space);
    const auto cpu = static_cast<rlim_t>(run.limits.cpu_seconds + 0.999);
    set_limit(RLIMIT_CPU, cpu, cpu + 2);
    set_limit(RLIMIT_CORE, 0, 0);
    const int null_fd = ::open("/dev/null", O_RDONLY);
    ::dup2(null_fd, 0);
    ::dup2(out_fd, 1);
    ::dup2(err_fd, 2);
    if (::chdir(run.cwd.c_str()) != 0) _exit(126);
    ::execve(argv[0], argv, envp);
    _exit(127);
}

/// True when a process of group `group` is still running: neither exited (a zombie waiting for
/// init to reap it) nor the sanitizer runtime's own llvm-symbolizer, which clang's sanitizers
/// start to name the frames of a report or of a suppressed leak and never reap.
bool group_still_running(pid_t group) {
    const std::string ours = std::to_string(group);
    for (const std::filesystem::directory_entry& entry :
         std::filesystem::directory_iterator("/proc", std::filesystem::directory_options::skip_permission_denied)) {
        const std::string name = entry.path().filename().string();
        if (name.empty() || !std::all_of(name.begin(), name.end(), [](unsigned char c) { return std::isdigit(c); }))
            continue;
        std::ifstream file(entry.path() / "stat");
        std::string stat;
        if (!std::getline(file, stat)) continue;  // ended meanwhile
        // pid (comm) state ppid pgrp ...: comm may hold spaces and parentheses, so split at the last ')'.
        const std::size_t open = stat.find('('), close = stat.rfind(')');
        if (open == std::string::npos || close == std::string::npos || close < open) continue;
        const std::string comm = stat.substr(open + 1, close - open - 1);
        std::istringstream rest(stat.substr(close + 1));
        std::string state, ppid, pgrp;
        rest >> state >> ppid >> pgrp;
        if (pgrp != ours || state == "Z" || state == "X" || comm == "llvm-symbolizer") continue;
        return true;
    }
    return false;
}

}  // namespace

bool sanitized_build() { return caustica::sanitized_build; }

double pace_factor() { return sanitized_build() ? 4.0 : 1.0; }

std::size_t rss_bound(std::size_t bytes) { return sanitized_build() ? 4 * bytes + 1 * gib : bytes; }

std::string Outcome::describe() const {
    std::ostringstream s;
    s << "exit " << exit_code;
    if (signal) s << ", signal " << signal << " (" << strsignal(signal) << ")";
    s << ", " << seconds << " s, peak RSS " << peak_rss / mib << " MiB";
    if (!killed.empty()) s << ", killed by the test: " << killed;
    if (stragglers) s << ", processes of its group outlived it";
    s << " (time bounds x" << time_factor() << ")";
    s << "\n--- stderr:\n" << err.substr(0, 4000) << "\n--- stdout:\n" << out.substr(0, 2000);
    return s.str();
}

Outcome run_child(const Launch& run) {
    Outcome outcome;
    int out_pipe[2], err_pipe[2];
    if (::pipe2(out_pipe, O_CLOEXEC) != 0 || ::pipe2(err_pipe, O_CLOEXEC) != 0) {
        ADD_FAILURE() << "pipe: " << std::strerror(errno);
        return outcome;
    }
    std::vector<std::string> arg_strings{run.program.empty() ? caustica_binary() : run.program};
    arg_strings.insert(arg_strings.end(), run.args.begin(), run.args.end());
    std::vector<std::string> env_strings = child_environment(run.env);
    std::vector<char*> argv = pointers(arg_strings);
    std::vector<char*> envp = pointers(env_strings);
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid < 0) {
        ADD_FAILURE() << "fork: " << std::strerror(errno);
        return outcome;
    }
    if (pid == 0) become_child(run, argv.data(), envp.data(), out_pipe[1], err_pipe[1]);
    ::setpgid(pid, pid);  // also here, so that signal_group works before the child gets to it
    ::close(out_pipe[1]);
    ::close(err_pipe[1]);
    ::fcntl(out_pipe[0], F_SETFL, O_NONBLOCK);
    ::fcntl(err_pipe[0], F_SETFL, O_NONBLOCK);

    Capture out, err;
    bool out_open = true, err_open = true;
    int status = 0;
    rusage usage{};
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    for (;;) {
        const pid_t done = ::wait4(pid, &status, WNOHANG, &usage);
        if (done == pid) break;
        const double t = elapsed();
        if (outcome.killed.empty()) {
            if (t > run.limits.wall_seconds) {
                outcome.killed = "wall-clock limit of " + std::to_string(run.limits.wall_seconds) + " s";
            } else if (const std::size_t rss = resident_bytes(pid); rss > run.limits.resident) {
                outcome.killed = "resident size " + std::to_string(rss / mib) + " MiB over the limit of " +
                                 std::to_string(run.limits.resident / mib) + " MiB";
            }
            if (!outcome.killed.empty()) ::kill(-pid, SIGKILL);
        }
        if (run.tick && outcome.killed.empty()) run.tick(t, pid, err.head);
        pollfd fds[2] = {{out_open ? out_pipe[0] : -1, POLLIN, 0}, {err_open ? err_pipe[0] : -1, POLLIN, 0}};
        ::poll(fds, 2, 5);
        if (out_open) out_open = drain(out_pipe[0], out);
        if (err_open) err_open = drain(err_pipe[0], err);
    }
    outcome.seconds = elapsed();
    // Whatever is left in the pipes (a straggler holding them open must not block us).
    for (int i = 0; i < 20 && (out_open || err_open); ++i) {
        pollfd fds[2] = {{out_open ? out_pipe[0] : -1, POLLIN, 0}, {err_open ? err_pipe[0] : -1, POLLIN, 0}};
        ::poll(fds, 2, 5);
        if (out_open) out_open = drain(out_pipe[0], out);
        if (err_open) err_open = drain(err_pipe[0], err);
    }
    outcome.stragglers = group_still_running(pid);
    ::kill(-pid, SIGKILL);  // whatever is left of the group, zombies and symbolizer included
    ::close(out_pipe[0]);
    ::close(err_pipe[0]);
    outcome.out = out.text();
    outcome.err = err.text();
    outcome.peak_rss = static_cast<std::size_t>(usage.ru_maxrss) * 1024;
    if (WIFEXITED(status)) outcome.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
    if (const char* verbose = std::getenv("CAUSTICA_REPRO_VERBOSE"); verbose && *verbose == '1')
        std::printf("[ child    ] %s\n", outcome.describe().c_str());
    return outcome;
}

std::string caustica_binary() {
    const char* chosen = std::getenv("CAUSTICA_REPRO_BINARY");
    return chosen && *chosen ? chosen : CAUSTICA_BINARY;
}

void signal_group(pid_t child, int signal) { ::kill(-child, signal); }

fs::path repro_source(const std::string& relative) {
    return fs::path(CAUSTICA_SOURCE_DIR) / "tests" / "repro" / relative;
}

fs::path regression_source(const std::string& relative) {
    return fs::path(CAUSTICA_SOURCE_DIR) / "fuzz" / "regressions" / relative;
}

Tree snapshot(const fs::path& root) {
    Tree tree;
    std::error_code error;
    for (auto it = fs::recursive_directory_iterator(root, fs::directory_options::skip_permission_denied, error);
         !error && it != fs::recursive_directory_iterator(); it.increment(error)) {
        struct stat st{};
        if (::lstat(it->path().c_str(), &st) != 0) continue;
        // A folder counts by its presence only (its size and time change with its entries).
        const bool folder = S_ISDIR(st.st_mode);
        const long long mtime =
            folder ? 0 : static_cast<long long>(st.st_mtim.tv_sec) * 1'000'000'000LL + st.st_mtim.tv_nsec;
        tree[it->path().lexically_relative(root).string()] = {folder ? 0 : static_cast<std::uintmax_t>(st.st_size),
                                                              mtime};
    }
    return tree;
}

std::vector<std::string> changes(const Tree& before, const Tree& after) {
    std::vector<std::string> found;
    for (const auto& [name, info] : after) {
        auto old = before.find(name);
        if (old == before.end()) found.push_back("+" + name);
        else if (old->second != info) found.push_back("~" + name);
    }
    for (const auto& [name, info] : before)
        if (!after.count(name)) found.push_back("-" + name);
    std::sort(found.begin(), found.end());
    return found;
}

Scratch::Scratch() {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(test->test_suite_name()) + "." + test->name();
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_') c = '_';
    root_ = fs::temp_directory_path() / ("caustica_repro_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(root_);
    fs::create_directories(root_);
}

Scratch::~Scratch() {
    std::error_code error;
    fs::remove_all(root_, error);
}

fs::path Scratch::write(const std::string& relative, const std::string& text) const {
    const fs::path path = root_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

fs::path Scratch::copy(const std::string& from, const std::string& to) const {
    return copy_path(repro_source(from), to);
}

fs::path Scratch::copy_path(const fs::path& source, const std::string& to) const {
    const fs::path path = root_ / to;
    fs::create_directories(path.parent_path());
    fs::copy_file(source, path, fs::copy_options::overwrite_existing);
    fs::permissions(path, fs::perms::owner_read | fs::perms::owner_write, fs::perm_options::add);
    return path;
}

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

bool names_location(const std::string& text, const std::string& file, int line) {
    const std::string wanted = file + ":" + std::to_string(line) + ": ";
    for (std::size_t at = text.find(wanted); at != std::string::npos; at = text.find(wanted, at + 1)) {
        if (at == 0) return true;
        const char before = text[at - 1];
        if (before == '\n' || before == ' ' || before == '/' || before == '\'') return true;
    }
    return false;
}

Outcome caustica_run(const fs::path& cwd, std::vector<std::string> args, double wall_seconds, std::size_t resident,
                     std::vector<std::pair<std::string, std::string>> env, std::size_t address_space) {
    Launch run;
    run.cwd = cwd;
    run.args = std::move(args);
    run.env = std::move(env);
    run.limits.wall_seconds = wall_seconds * time_factor();
    run.limits.cpu_seconds *= time_factor();
    run.limits.resident = rss_bound(resident);
    run.limits.address_space = address_space;
    return run_child(run);
}

bool mentions(const std::string& text, std::string word) {
    std::string lower = text;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    std::transform(word.begin(), word.end(), word.begin(), [](unsigned char c) { return std::tolower(c); });
    return lower.find(word) != std::string::npos;
}

void expect_scene_error(const Outcome& o, const std::string& file, int line) {
    EXPECT_EQ(o.exit_code, 2) << o.describe();
    EXPECT_TRUE(names_location(o.err, file, line)) << "expected '" << file << ":" << line << ": ...'\n" << o.describe();
    EXPECT_FALSE(o.stragglers) << o.describe();
}

void expect_outcome(const Outcome& o, const fs::path& output, int width, int height, const std::string& file,
                    const Expected& expected) {
    ASSERT_EQ(o.signal, 0) << o.describe();
    ASSERT_TRUE(o.killed.empty()) << o.describe();
    EXPECT_FALSE(o.stragglers) << o.describe();
    if (expected.line == 0) {
        ASSERT_EQ(o.exit_code, 0) << o.describe();
        ASSERT_TRUE(fs::exists(output)) << o.describe();
        const Png8 png = read_png(output.string());
        EXPECT_EQ(png.width, width);
        EXPECT_EQ(png.height, height);
        return;
    }
    expect_scene_error(o, file, expected.line);
    const std::string located = file + ":" + std::to_string(expected.line) + ": " + expected.call + ":";
    EXPECT_NE(o.err.find(located), std::string::npos) << "expected '" << located << "'\n" << o.describe();
    EXPECT_FALSE(fs::exists(output)) << o.describe();
}

}  // namespace caustica::repro
