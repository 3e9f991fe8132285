// load_scene_script: the script runs in a child process, so that nothing it does can outlast its
// limits or harm the caller. The parent is the watchdog: it asks the child to stop at the time
// limit (SIGUSR1: allocations fail, the hook raises), stops it for good a grace period later or at
// once on cancel (SIGKILL), and turns a crash of the interpreter into an error message. The child
// runs under an address-space cap besides the loader's own budget, and sends back its SceneScript
// as bytes (scene_wire.h) or its error.
#include "core/lua/lua_context.h"
#include "core/lua/scene_wire.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <new>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define CAUSTICA_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
#define CAUSTICA_SANITIZED 1
#endif
#endif

namespace caustica {
namespace {

using namespace scene_lua;
using Clock = std::chrono::steady_clock;

/// From the time limit to the request to stop (the child's own hook normally stops it first).
constexpr auto stop_request_delay = std::chrono::milliseconds(200);
/// From the request to stop to the hard stop.
constexpr auto grace_period = std::chrono::milliseconds(800);
/// What the child may use besides the script's budget (the interpreter, the C++ heap, the reply).
constexpr std::size_t address_space_slack = std::size_t(512) << 20;

/// The page the child writes its current line to, shared with the parent.
class SharedPage {
public:
    SharedPage() {
        void* page = ::mmap(nullptr, sizeof(SharedProgress), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
        if (page == MAP_FAILED) throw std::runtime_error(std::string("cannot map a shared page: ") + std::strerror(errno));
        progress_ = new (page) SharedProgress();
    }
    ~SharedPage() { ::munmap(progress_, sizeof(SharedProgress)); }
    SharedPage(const SharedPage&) = delete;
    SharedPage& operator=(const SharedPage&) = delete;

    SharedProgress* get() const { return progress_; }
    /// "file:line" of the last line the child reported, or `fallback`.
    std::string where(const std::string& fallback) const {
        const std::string file(progress_->file, strnlen(progress_->file, sizeof progress_->file));
        if (file.empty() || progress_->line <= 0) return fallback;
        return file + ":" + std::to_string(progress_->line);
    }

private:
    SharedProgress* progress_ = nullptr;
};

void on_stop_request(int) { stop_requested = 1; }

/// VmData of this process in bytes (0 when /proc cannot say).
std::size_t data_segment_bytes() {
    std::ifstream status("/proc/self/status");
    std::string key;
    while (status >> key) {
        if (key == "VmData:") {
            std::size_t kib = 0;
            status >> kib;
            return kib << 10;
        }
        status.ignore(1 << 16, '\n');
    }
    return 0;
}

bool write_all(int fd, const char* data, std::size_t size) {
    while (size) {
        const ssize_t done = ::write(fd, data, size);
        if (done < 0 && errno == EINTR) continue;
        if (done <= 0) return false;
        data += done;
        size -= static_cast<std::size_t>(done);
    }
    return true;
}

/// The child: runs the script and writes one reply, a kind letter and its payload:
/// 'O' + scene bytes, 'E' + message (InputError), 'C' (cancelled), 'X' + message (anything else).
[[noreturn]] void run_child(int out, const std::string& path, const LoadSettings& settings, SharedProgress* progress,
                            pid_t parent) {
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(1);
    ::signal(SIGINT, SIG_IGN);  // the parent stops the child on Ctrl-C
    ::signal(SIGUSR1, on_stop_request);
    sigset_t unblock;
    sigemptyset(&unblock);
    sigaddset(&unblock, SIGUSR1);
    ::pthread_sigmask(SIG_UNBLOCK, &unblock, nullptr);
    const rlimit no_core{0, 0};
    ::setrlimit(RLIMIT_CORE, &no_core);
#ifndef CAUSTICA_SANITIZED
    if (settings.memory_limit_bytes != 0) {
        const std::size_t base = data_segment_bytes();
        if (base != 0) {
            const rlim_t cap = base + settings.memory_limit_bytes + settings.memory_limit_bytes / 4 + address_space_slack;
            const rlimit data{cap, cap};
            ::setrlimit(RLIMIT_DATA, &data);
        }
    }
#endif
    std::string reply;
    try {
        try {
            reply = "O" + encode_scene_script(run_script(path, settings, progress));
        } catch (const ScriptCancelled&) {
            reply = "C";
        } catch (const InputError& e) {
            reply = std::string("E") + e.what();
        } catch (const std::bad_alloc&) {
            reply = "Mout of memory";
        } catch (const std::exception& e) {
            reply = std::string("X") + e.what();
        }
    } catch (...) {
        reply = "Mout of memory";
    }
    std::fflush(stdout);
    std::fflush(stderr);
    const std::uint64_t size = reply.size();
    const bool sent = write_all(out, reinterpret_cast<const char*>(&size), sizeof size) &&
                      write_all(out, reply.data(), reply.size());
    ::_exit(sent ? 0 : 1);
}

/// Owns the child: kills and reaps it unless it was reaped already.
class Child {
public:
    explicit Child(pid_t pid) : pid_(pid) {}
    Child(const Child&) = delete;
    Child& operator=(const Child&) = delete;
    ~Child() { kill(); }

    void signal(int number) const {
        if (pid_ > 0) ::kill(pid_, number);
    }
    void kill() {
        if (pid_ <= 0) return;
        ::kill(pid_, SIGKILL);
        wait();
    }
    /// Waits for the child to end; its wait status.
    int wait() {
        int status = 0;
        while (pid_ > 0 && ::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
        }
        pid_ = -1;
        return status;
    }

private:
    pid_t pid_;
};

std::string signal_text(int number) {
    const char* name = ::strsignal(number);
    return "signal " + std::to_string(number) + (name ? std::string(" (") + name + ")" : std::string());
}

}  // namespace

SceneScript load_scene_script(const std::string& path, const LoadSettings& settings) {
    if (settings.cancel && settings.cancel->load()) throw ScriptCancelled();
    SharedPage page;
    int pipe_ends[2];
    if (::pipe2(pipe_ends, O_CLOEXEC) != 0)
        throw std::runtime_error(std::string("cannot start the scene loader: ") + std::strerror(errno));
    std::fflush(nullptr);  // nothing buffered here may be written twice by the child
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid == 0) {
        ::close(pipe_ends[0]);
        run_child(pipe_ends[1], path, settings, page.get(), parent);
    }
    const int error = errno;
    ::close(pipe_ends[1]);
    if (pid < 0) {
        ::close(pipe_ends[0]);
        throw std::runtime_error(std::string("cannot start the scene loader: ") + std::strerror(error));
    }
    Child child(pid);
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } reading{pipe_ends[0]};

    const bool limited = settings.timeout_seconds > 0.0;
    const auto start = Clock::now();
    const auto limit = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(std::min(settings.timeout_seconds, 1e9)));
    bool stop_sent = false;
    std::string reply;
    char buffer[1 << 16];
    for (;;) {
        pollfd ready{reading.fd, POLLIN, 0};
        const int polled = ::poll(&ready, 1, 50);
        if (polled > 0) {
            const ssize_t got = ::read(reading.fd, buffer, sizeof buffer);
            if (got == 0) break;
            if (got > 0) reply.append(buffer, static_cast<std::size_t>(got));
            else if (errno != EINTR && errno != EAGAIN) break;
        }
        if (settings.cancel && settings.cancel->load()) throw ScriptCancelled();  // ~Child kills it
        if (!limited) continue;
        const auto elapsed = Clock::now() - start;
        if (!stop_sent && elapsed >= limit + stop_request_delay) {
            child.signal(SIGUSR1);
            stop_sent = true;
        }
        if (elapsed >= limit + stop_request_delay + grace_period) {
            child.kill();
            throw InputError(page.where(path) + ": script stopped after " +
                             format_number(settings.timeout_seconds) +
                             " s (--script-timeout), inside a library call that had to be stopped from outside");
        }
    }
    const int status = child.wait();
    std::uint64_t size = 0;
    if (reply.size() >= sizeof size) std::memcpy(&size, reply.data(), sizeof size);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || reply.size() < sizeof size + 1 ||
        size != reply.size() - sizeof size) {
        std::string how = WIFSIGNALED(status) ? "was ended by " + signal_text(WTERMSIG(status))
                                              : "ended without an answer";
        throw InputError(page.where(path) + ": the scene interpreter " + how +
                         " (a bug in caustica: please report it with the scene)");
    }
    const char kind = reply[sizeof size];
    const std::string_view payload(reply.data() + sizeof size + 1, reply.size() - sizeof size - 1);
    switch (kind) {
    case 'O': return decode_scene_script(payload);
    case 'C': throw ScriptCancelled();
    case 'E': throw InputError(std::string(payload));
    case 'M': throw InputError(page.where(path) + ": " + std::string(payload));
    default: throw InputError(path + ": " + std::string(payload));
    }
}

}  // namespace caustica
