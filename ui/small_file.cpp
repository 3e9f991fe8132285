#include "ui/small_file.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace caustica::ui {
namespace {

namespace fs = std::filesystem;

std::string too_large(std::size_t limit) { return "larger than " + std::to_string(limit >> 20) + " MiB"; }

/// Reads from `fd` until `text` is full or the file ends; the count read ("problem" says why it
/// stopped early on an error).
std::size_t read_up_to(int fd, std::string& text, std::string& problem) {
    std::size_t got = 0;
    while (got < text.size()) {
        const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            problem = std::string("cannot be read (") + std::strerror(errno) + ")";
            break;
        }
        if (n == 0) break;
        got += static_cast<std::size_t>(n);
    }
    return got;
}

/// Creates the folder `file` goes in, if missing (an error shows when the file is opened).
void create_folder_of(const std::string& file) {
    std::error_code ec;
    fs::create_directories(fs::path(file).parent_path(), ec);
}

}  // namespace

SmallFile read_small_file(const std::string& path, std::size_t limit, OverLimit over) {
    SmallFile result;
    // O_NONBLOCK: opening a FIFO must not wait for a writer; the type is checked on the open file
    // (fstat), so it cannot be swapped between the check and the read.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        if (errno == ENOENT) return result;  // missing: nothing to read, fine to create
        result.exists = true;
        result.problem = std::string("cannot be opened (") + std::strerror(errno) + ")";
        return result;
    }
    result.exists = true;
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        result.problem = std::string("cannot be read (") + std::strerror(errno) + ")";
    } else if (S_ISDIR(st.st_mode)) {
        result.problem = "is a folder, not a file";
    } else if (S_ISFIFO(st.st_mode)) {
        result.problem = "is a named pipe (FIFO), not a regular file";
    } else if (!S_ISREG(st.st_mode)) {
        result.problem = "is a device or socket, not a regular file";
    } else if (over == OverLimit::refuse && static_cast<std::uintmax_t>(st.st_size) > limit) {
        result.over_limit = true;
        result.problem = too_large(limit);
    } else {
        std::string text(limit + 1, '\0');  // one more byte tells a file over the limit
        const std::size_t got = read_up_to(fd, text, result.problem);
        if (result.problem.empty()) {
            result.over_limit = got > limit;
            if (result.over_limit) result.problem = too_large(limit);
            if (!result.over_limit || over == OverLimit::read_start) {
                text.resize(std::min(got, limit));
                result.text = std::move(text);
            }
        }
    }
    ::close(fd);
    return result;
}

std::string write_atomically(const std::string& file, const std::string& text) {
    static std::atomic<unsigned> counter{0};
    create_folder_of(file);
    const std::string temporary =
        file + ".tmp." + std::to_string(static_cast<long>(::getpid())) + "." + std::to_string(counter++);
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) return std::strerror(errno);
    std::size_t done = 0;
    std::string problem;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            problem = std::strerror(errno);
            break;
        }
        done += static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0 && problem.empty()) problem = std::strerror(errno);
    std::error_code ec;
    if (problem.empty()) {
        fs::rename(temporary, file, ec);
        if (ec) problem = ec.message();
    }
    if (!problem.empty()) fs::remove(temporary, ec);
    return problem;
}

std::string escape_field(const std::string& text) {
    std::string out;
    for (const char c : text) {
        if (c == '\\') out += "\\\\";
        else if (c == '\t') out += "\\t";
        else if (c == '\n') out += "\\n";
        else if (c == '\r') out += "\\r";
        else out += c;
    }
    return out;
}

std::string unescape_field(const std::string& text) {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '\\' || i + 1 == text.size()) {
            out += text[i];
            continue;
        }
        const char next = text[i + 1];
        if (next == '\\') out += '\\';
        else if (next == 't') out += '\t';
        else if (next == 'n') out += '\n';
        else if (next == 'r') out += '\r';
        else {
            out += '\\';  // not an escape we write: keep it as it is
            continue;
        }
        ++i;
    }
    return out;
}

LinesWritten write_newest_lines(const std::string& file, const std::vector<std::string>& lines, std::size_t limit) {
    LinesWritten written;
    written.kept.assign(lines.size(), false);
    std::size_t size = 0;
    for (std::size_t i = lines.size(); i-- > 0;) {
        if (size + lines[i].size() + 1 <= limit) {
            size += lines[i].size() + 1;
            written.kept[i] = true;
        } else {
            ++written.dropped;
        }
    }
    std::string text;
    text.reserve(size);
    for (std::size_t i = 0; i < lines.size(); ++i)
        if (written.kept[i]) text.append(lines[i]).push_back('\n');
    written.problem = write_atomically(file, text);
    return written;
}

FileLock::FileLock(const std::string& lock_file, double wait_seconds) {
    create_folder_of(lock_file);
    // O_NOFOLLOW: a symlink planted as the lock file is refused rather than created through.
    const int fd = ::open(lock_file.c_str(), O_RDWR | O_CREAT | O_NONBLOCK | O_CLOEXEC | O_NOCTTY | O_NOFOLLOW, 0644);
    if (fd < 0) {
        problem_ = std::string("cannot be opened (") + std::strerror(errno) + ")";
        return;
    }
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        problem_ = "is not a regular file";
        ::close(fd);
        return;
    }
    // Polled rather than waited for in flock(): a blocking flock cannot be given a time limit
    // without a signal, and a preview stopped while it held the lock must not freeze this one.
    using clock = std::chrono::steady_clock;
    const auto give_up = clock::now() + std::chrono::duration<double>(wait_seconds);
    while (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
        if (errno == EINTR) continue;
        if (errno != EWOULDBLOCK) {
            problem_ = std::string("cannot be locked (") + std::strerror(errno) + ")";
        } else if (clock::now() >= give_up) {
            char seconds[32];
            std::snprintf(seconds, sizeof seconds, "%g", wait_seconds);
            problem_ = std::string("still held by another process after ") + seconds + " s";
        } else {
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
            continue;
        }
        ::close(fd);
        return;
    }
    fd_ = fd;
}

FileLock::~FileLock() {
    if (fd_ >= 0) ::close(fd_);  // closing the only descriptor of the open file releases its flock
}

}  // namespace caustica::ui
