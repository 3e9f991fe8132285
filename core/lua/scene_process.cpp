// load_scene_script: the script runs in a child process (caustica-scene-loader, started fresh:
// a fork of a threaded caller could inherit a lock another thread held), so that nothing it does
// can outlast its limits or harm the caller. The parent is the watchdog: it asks the child to stop
// at the time limit (SIGUSR1: allocations fail, the hook raises), stops it for good a grace period
// later or at once on cancel (SIGKILL), and turns a crash of the interpreter into an error
// message. The child runs under a data-segment cap besides the loader's own budget, and sends back
// its SceneScript as bytes (scene_wire.h) or its error (loader_child.h has the protocol).
#include "core/lua/loader_child.h"
#include "core/lua/scene_wire.h"
#include "core/util/printable_text.h"

#include <spawn.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string_view>

extern char** environ;

namespace caustica {
namespace {

using namespace scene_lua;
using Clock = std::chrono::steady_clock;

/// From the time limit to the request to stop (the child's own hook normally stops it first).
constexpr auto stop_request_delay = std::chrono::milliseconds(200);
/// From the request to stop to the hard stop.
constexpr auto grace_period = std::chrono::milliseconds(800);

/// The page the child writes its current line to, shared with the parent through a memfd.
class SharedPage {
public:
    SharedPage() {
        fd_ = ::memfd_create("caustica-scene-progress", MFD_CLOEXEC);
        if (fd_ < 0 || ::ftruncate(fd_, sizeof(SharedProgress)) != 0) fail("cannot make a shared page");
        void* page = ::mmap(nullptr, sizeof(SharedProgress), PROT_READ | PROT_WRITE, MAP_SHARED, fd_, 0);
        if (page == MAP_FAILED) fail("cannot map a shared page");
        progress_ = new (page) SharedProgress();
    }
    ~SharedPage() {
        if (progress_) ::munmap(progress_, sizeof(SharedProgress));
        if (fd_ >= 0) ::close(fd_);
    }
    SharedPage(const SharedPage&) = delete;
    SharedPage& operator=(const SharedPage&) = delete;

    int fd() const { return fd_; }
    SharedProgress* get() const { return progress_; }
    /// "file:line" of the last line the child reported, or `fallback`.
    std::string where(const std::string& fallback) const {
        const std::string file(progress_->file, strnlen(progress_->file, sizeof progress_->file));
        if (file.empty() || progress_->line <= 0) return fallback;
        return file + ":" + std::to_string(progress_->line);
    }

private:
    [[noreturn]] void fail(const char* what) {
        const int error = errno;
        if (fd_ >= 0) ::close(fd_);
        throw std::runtime_error(std::string(what) + ": " + std::strerror(error));
    }
    int fd_ = -1;
    SharedProgress* progress_ = nullptr;
};

/// A pipe whose ends are numbered 10 and up (never 3-5, which the child's ends are moved to) and
/// close on exec.
struct Pipe {
    int read = -1, write = -1;
    Pipe() {
        int ends[2];
        if (::pipe2(ends, O_CLOEXEC) != 0)
            throw std::runtime_error(std::string("cannot start the scene loader: ") + std::strerror(errno));
        read = ::fcntl(ends[0], F_DUPFD_CLOEXEC, 10);
        write = ::fcntl(ends[1], F_DUPFD_CLOEXEC, 10);
        ::close(ends[0]);
        ::close(ends[1]);
        if (read < 0 || write < 0) throw std::runtime_error("cannot start the scene loader: no descriptors left");
    }
    ~Pipe() {
        close_read();
        close_write();
    }
    Pipe(const Pipe&) = delete;
    Pipe& operator=(const Pipe&) = delete;
    void close_read() {
        if (read >= 0) ::close(read);
        read = -1;
    }
    void close_write() {
        if (write >= 0) ::close(write);
        write = -1;
    }
};

/// "5", "0.5": the time limit as the user gave it.
std::string seconds_text(double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", seconds);
    return text;
}

/// The loader executable: $CAUSTICA_SCENE_LOADER, else beside this executable, else where the
/// build put it.
std::string loader_executable() {
    if (const char* given = std::getenv("CAUSTICA_SCENE_LOADER"); given && *given) return given;
    char self[4096];
    const ssize_t length = ::readlink("/proc/self/exe", self, sizeof self - 1);
    if (length > 0) {
        std::string beside(self, static_cast<std::size_t>(length));
        beside = beside.substr(0, beside.rfind('/') + 1) + "caustica-scene-loader";
        if (::access(beside.c_str(), X_OK) == 0) return beside;
    }
    return CAUSTICA_SCENE_LOADER_PATH;
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

/// The child's reply as it arrives (loader_child.h has its layout): all of a scene, at most a
/// bounded message of any other kind. Past that bound the bytes are counted, not kept, so that a
/// broken or hostile child cannot make this process hold a huge message (docs/RELIABILITY.md,
/// "Script text reaches the user bounded and visible").
class ReplyBytes {
public:
    /// The 8-byte length and the kind letter.
    static constexpr std::size_t header_bytes = sizeof(std::uint64_t) + 1;
    /// The most a working child sends after the header of a message (loader_child.cpp bounds it).
    static constexpr std::size_t message_bytes = printable_text_max_bytes(shown_message_limit);

    void add(std::string_view data) {
        received_ += data.size();
        if (bytes_.size() < header_bytes) {
            const std::size_t head = std::min(data.size(), header_bytes - bytes_.size());
            bytes_.append(data.substr(0, head));
            data.remove_prefix(head);
        }
        const bool bounded = bytes_.size() >= header_bytes && kind() != 'O';
        const std::size_t kept = bounded ? std::min(data.size(), message_bytes - kept_payload()) : data.size();
        bytes_.append(data.substr(0, kept));
        dropped_ += data.size() - kept;
    }
    /// Whether the reply is whole: its length says how many bytes followed it.
    bool complete() const {
        std::uint64_t size = 0;
        if (bytes_.size() < header_bytes) return false;
        std::memcpy(&size, bytes_.data(), sizeof size);
        return size == received_ - sizeof size;
    }
    char kind() const { return bytes_.size() < header_bytes ? '\0' : bytes_[header_bytes - 1]; }
    /// What follows the kind letter, as far as it was kept.
    std::string_view payload() const {
        return std::string_view(bytes_).substr(std::min(bytes_.size(), header_bytes));
    }
    /// The message it carries: unchanged from a working child (which made it printable and bounded
    /// it), printable and bounded from any other, with the bytes not kept counted in.
    std::string message() const { return printable_text(payload(), message_bytes, dropped_); }

private:
    std::size_t kept_payload() const { return bytes_.size() < header_bytes ? 0 : bytes_.size() - header_bytes; }
    std::string bytes_;
    std::size_t received_ = 0;
    std::size_t dropped_ = 0;
};

std::string signal_text(int number) {
    const char* name = ::strsignal(number);
    return "signal " + std::to_string(number) + (name ? std::string(" (") + name + ")" : std::string());
}

}  // namespace

SceneScript load_scene_script(const std::string& path, const LoadSettings& settings) {
    if (settings.cancel && settings.cancel->load()) throw ScriptCancelled();
    SharedPage page;
    Pipe request, answer;
    const int progress = ::fcntl(page.fd(), F_DUPFD_CLOEXEC, 10);
    struct Closer {
        int fd;
        ~Closer() {
            if (fd >= 0) ::close(fd);
        }
    } progress_closer{progress};
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, request.read, request_fd);
    posix_spawn_file_actions_adddup2(&actions, answer.write, reply_fd);
    posix_spawn_file_actions_adddup2(&actions, progress, progress_fd);
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    sigaddset(&defaults, SIGUSR1);
    sigaddset(&defaults, SIGPIPE);
    posix_spawnattr_setsigmask(&attributes, &none);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
    const std::string program = loader_executable();
    char* const argv[] = {const_cast<char*>(program.c_str()), nullptr};
    std::fflush(nullptr);  // nothing buffered here may be written out of order with the script's output
    pid_t pid = -1;
    const int spawned = ::posix_spawn(&pid, program.c_str(), &actions, &attributes, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    if (spawned != 0)
        throw std::runtime_error("cannot start the scene loader " + program + ": " + std::strerror(spawned));
    Child child(pid);
    request.close_read();
    answer.close_write();
    {
        // A child that died before reading is reported from its exit status below; its closed
        // pipe must not raise SIGPIPE here, so the signal is blocked and any pending one taken.
        sigset_t pipe_signal, previous;
        sigemptyset(&pipe_signal);
        sigaddset(&pipe_signal, SIGPIPE);
        ::pthread_sigmask(SIG_BLOCK, &pipe_signal, &previous);
        const std::string request_bytes = encode_load_request(path, settings);
        if (!write_all(request.write, request_bytes.data(), request_bytes.size())) {
            const timespec no_wait{0, 0};
            ::sigtimedwait(&pipe_signal, nullptr, &no_wait);
        }
        ::pthread_sigmask(SIG_SETMASK, &previous, nullptr);
        request.close_write();
    }
    const int reading_fd = answer.read;

    const bool limited = settings.timeout_seconds > 0.0;
    const auto start = Clock::now();
    const auto limit = std::chrono::duration_cast<Clock::duration>(
        std::chrono::duration<double>(std::min(settings.timeout_seconds, 1e9)));
    bool stop_sent = false;
    ReplyBytes reply;
    char buffer[1 << 16];
    for (;;) {
        pollfd ready{reading_fd, POLLIN, 0};
        const int polled = ::poll(&ready, 1, 50);
        if (polled > 0) {
            const ssize_t got = ::read(reading_fd, buffer, sizeof buffer);
            if (got == 0) break;
            if (got > 0) reply.add(std::string_view(buffer, static_cast<std::size_t>(got)));
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
                             seconds_text(settings.timeout_seconds) +
                             " s (--script-timeout), inside a library call that had to be stopped from outside");
        }
    }
    const int status = child.wait();
    if (settings.cancel && settings.cancel->load()) throw ScriptCancelled();
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !reply.complete()) {
        std::string how = WIFSIGNALED(status) ? "was ended by " + signal_text(WTERMSIG(status))
                                              : "ended without an answer";
        throw InputError(page.where(path) + ": the scene interpreter " + how +
                         " (a bug in caustica: please report it with the scene)");
    }
    switch (reply.kind()) {
    case 'O': return decode_scene_script(reply.payload());
    case 'C': throw ScriptCancelled();
    case 'E': throw InputError(reply.message());
    case 'M': throw InputError(page.where(path) + ": " + reply.message());
    default: throw InputError(path + ": " + reply.message());
    }
}

}  // namespace caustica
