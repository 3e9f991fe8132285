#include "core/io/atomic_file.h"

#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <limits>
#include <memory>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

namespace caustica {
namespace {

/// What follows the output's name in a temporary: of a write, or of the check before rendering.
constexpr const char* write_marker = ".caustica-tmp-";
constexpr const char* probe_marker = ".caustica-probe-";

/// The temporary of one write in progress, readable from a signal handler: `sequence` is odd
/// while the name changes, so a handler that sees it change skips a torn name.
struct TemporarySlot {
    std::atomic<bool> claimed{false};
    std::atomic<bool> live{false};
    std::atomic<unsigned> sequence{0};
    std::atomic<char> name[4096];
};
constexpr int temporary_slot_count = 8;
TemporarySlot temporary_slots[temporary_slot_count];
static_assert(std::atomic<char>::is_always_lock_free && std::atomic<unsigned>::is_always_lock_free &&
              std::atomic<bool>::is_always_lock_free, "signal handlers need lock-free atomics");

/// Holds one slot for a write in progress and publishes its temporary's (absolute) name for the
/// signal handler. Without a free slot (more writes at once than slots) or with a name too long,
/// publishing does nothing: the write is then unprotected against a second signal, but still
/// cleaned up by cancellation and by stale-file removal.
class PublishedTemporary {
public:
    PublishedTemporary() {
        for (TemporarySlot& slot : temporary_slots) {
            bool expected = false;
            if (slot.claimed.compare_exchange_strong(expected, true)) {
                slot_ = &slot;
                return;
            }
        }
    }
    ~PublishedTemporary() {
        if (!slot_) return;
        slot_->live.store(false);
        slot_->claimed.store(false);
    }
    PublishedTemporary(const PublishedTemporary&) = delete;
    PublishedTemporary& operator=(const PublishedTemporary&) = delete;

    /// Makes `path` the name a signal handler removes.
    void publish(const std::string& path) {
        if (!slot_ || path.size() >= sizeof(TemporarySlot::name)) return;
        slot_->sequence.fetch_add(1);
        for (std::size_t i = 0; i < path.size(); ++i) slot_->name[i].store(path[i], std::memory_order_relaxed);
        slot_->name[path.size()].store('\0', std::memory_order_relaxed);
        slot_->sequence.fetch_add(1);
        slot_->live.store(true);
    }

private:
    TemporarySlot* slot_ = nullptr;
};

/// This machine's name as it appears in temporaries: letters, digits, '.' and '_' only, so the
/// name parses back; a temporary from another host is never taken for one of ours.
const std::string& host_tag() {
    static const std::string tag = [] {
        char host[256] = {};
        if (::gethostname(host, sizeof host - 1) != 0 || !host[0]) return std::string("host");
        std::string t;
        for (const char* c = host; *c && t.size() < 40; ++c)
            t += (std::isalnum(static_cast<unsigned char>(*c)) || *c == '.' || *c == '_') ? *c : '_';
        return t;
    }();
    return tag;
}

/// The process id of a temporary of ours on this host, or 0 when `name` is not one:
/// ".NAME.caustica-tmp-HOST-PID-N" (or -probe-) with HOST our host tag and PID, N decimal.
pid_t temporary_owner(const std::string& name) {
    const char* kind = write_marker;
    std::size_t marker = name.rfind(kind);
    if (marker == std::string::npos) marker = name.rfind(kind = probe_marker);
    if (name.size() < 2 || name[0] != '.' || marker == std::string::npos || marker < 2) return 0;
    const std::string rest = name.substr(marker + std::strlen(kind));  // HOST-PID-N
    const std::string& host = host_tag();
    if (rest.compare(0, host.size(), host) != 0 || rest.size() <= host.size() || rest[host.size()] != '-') return 0;
    const std::string numbers = rest.substr(host.size() + 1);  // PID-N
    const std::size_t dash = numbers.find('-');
    if (dash == 0 || dash == std::string::npos || dash + 1 == numbers.size() || dash > 9) return 0;
    for (std::size_t i = 0; i < numbers.size(); ++i)
        if (i != dash && !std::isdigit(static_cast<unsigned char>(numbers[i]))) return 0;
    const long pid = std::stol(numbers.substr(0, dash));
    return pid > 0 && pid <= std::numeric_limits<pid_t>::max() ? static_cast<pid_t>(pid) : 0;
}

/// A temporary's name for the output `name`: ".NAME.caustica-tmp-HOST-PID-N" (`marker` in the
/// middle), NAME shortened when the whole would pass the 255-byte file name limit.
std::string temporary_name(const std::string& name, unsigned serial, const char* marker) {
    const std::string suffix = marker + host_tag() + "-" + std::to_string(::getpid()) + "-" + std::to_string(serial);
    std::string stem = name;
    const std::size_t room = 255 - 1 - suffix.size();
    if (stem.size() > room) stem.resize(room);
    return "." + stem + suffix;
}

/// Creates the temporary for `name` in `folder` exclusively (never reusing a file that is there),
/// publishing its full path before it exists so that a signal between the two still finds it.
/// Returns the open stream and the temporary's name in `temporary`, or null with errno set.
FILE* create_temporary(const OutputFolder& folder, const std::string& name, const char* marker,
                       PublishedTemporary& published, std::string& temporary) {
    static std::atomic<unsigned> next_serial{0};
    for (int attempt = 0; attempt < 100; ++attempt) {
        temporary = temporary_name(name, next_serial.fetch_add(1), marker);
        published.publish((folder.path() / temporary).string());
        const int fd = ::openat(folder.fd(), temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno == EEXIST) continue;
        if (fd < 0) return nullptr;
        FILE* file = ::fdopen(fd, "wb");
        if (!file) {
            const int saved = errno;
            ::close(fd);
            ::unlinkat(folder.fd(), temporary.c_str(), 0);
            errno = saved;
        }
        return file;
    }
    errno = EEXIST;
    return nullptr;
}

}  // namespace

void remove_output_temporaries_from_signal_handler() noexcept {
    for (TemporarySlot& slot : temporary_slots) {
        if (!slot.live.load()) continue;
        const unsigned before = slot.sequence.load();
        if (before % 2 != 0) continue;
        char name[sizeof(TemporarySlot::name)];
        std::size_t i = 0;
        for (; i + 1 < sizeof name; ++i)
            if ((name[i] = slot.name[i].load(std::memory_order_relaxed)) == '\0') break;
        name[i] = '\0';
        std::atomic_thread_fence(std::memory_order_acquire);
        if (slot.sequence.load() != before || !slot.live.load()) continue;
        ::unlink(name);
    }
}

int remove_stale_output_temporaries(const std::string& folder) {
    namespace fs = std::filesystem;
    std::error_code ec;
    int removed = 0;
    const fs::path dir = folder.empty() ? fs::path(".") : fs::path(folder);
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        const pid_t owner = temporary_owner(name);
        if (owner == 0 || owner == ::getpid()) continue;
        struct stat st {};
        if (::lstat(it->path().c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != ::geteuid()) continue;
        if (::kill(owner, 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to judge
        if (::unlink(it->path().c_str()) == 0) ++removed;
    }
    return removed;
}

void write_file_atomic(const std::string& path, const FileWriteBody& body, const std::atomic<bool>* cancel,
                       OutputPlace place) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path target = fs::absolute(path, ec);
    if (ec) throw std::runtime_error("cannot write '" + path + "': " + ec.message());
    // Checked here, when writing, not only before rendering (docs/RELIABILITY.md, section 1).
    const OutputFolder folder(target, place, path);
    if (!folder.ok()) throw std::runtime_error("cannot write '" + path + "': " + std::strerror(folder.error()));
    remove_stale_output_temporaries(folder.path().string());

    const std::string name = target.filename().string();
    PublishedTemporary published;
    std::string temporary;
    std::unique_ptr<FILE, int (*)(FILE*)> file(create_temporary(folder, name, write_marker, published, temporary), std::fclose);
    if (!file) throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
    std::string error;
    FileWriteOutcome outcome = FileWriteOutcome::failed;
    try {
        outcome = body(file.get(), error);
    } catch (...) {
        file.reset();
        ::unlinkat(folder.fd(), temporary.c_str(), 0);
        throw;
    }
    if (outcome == FileWriteOutcome::written && (std::fflush(file.get()) != 0 || ::fsync(::fileno(file.get())) != 0)) {
        outcome = FileWriteOutcome::failed;
        error = std::strerror(errno);
    }
    if (std::fclose(file.release()) != 0 && outcome == FileWriteOutcome::written) {
        outcome = FileWriteOutcome::failed;
        error = std::strerror(errno);
    }
    if (outcome == FileWriteOutcome::written && cancel && cancel->load()) outcome = FileWriteOutcome::cancelled;
    if (outcome == FileWriteOutcome::written && ::renameat(folder.fd(), temporary.c_str(), folder.fd(), name.c_str()) != 0) {
        outcome = FileWriteOutcome::failed;
        error = std::strerror(errno);
    }
    if (outcome == FileWriteOutcome::written) return;
    ::unlinkat(folder.fd(), temporary.c_str(), 0);
    if (outcome == FileWriteOutcome::cancelled) throw ImageWriteCancelled("writing '" + path + "' was interrupted; nothing written");
    throw std::runtime_error("cannot write '" + path + "': " + (error.empty() ? std::string("write failed") : error));
}

std::string output_file_problem(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path target = fs::absolute(path, ec);
    if (ec) return ec.message();
    if (target.filename().string().size() > 255) return std::strerror(ENAMETOOLONG);
    if (fs::is_directory(target, ec)) return "it is a folder";
    const OutputFolder folder(target, OutputPlace::anywhere, path);
    if (!folder.ok()) return std::strerror(folder.error());
    PublishedTemporary published;
    std::string temporary;
    FILE* probe = create_temporary(folder, target.filename().string(), probe_marker, published, temporary);
    if (!probe) return std::strerror(errno);
    std::fclose(probe);
    ::unlinkat(folder.fd(), temporary.c_str(), 0);
    return {};
}

}  // namespace caustica
