// Reading a regular file by descriptor, for the image readers (core/io): opened without waiting
// on a FIFO, its type checked on the open file (so it cannot be swapped after the check), read at
// offsets. Errors read "PATH: reason".
#pragma once

#include "core/scene/source_location.h"

#include <cerrno>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <fcntl.h>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

namespace caustica::io {

/// An open file descriptor, closed on scope exit.
struct Descriptor {
    int fd = -1;
    Descriptor() = default;
    Descriptor(const Descriptor&) = delete;
    Descriptor& operator=(const Descriptor&) = delete;
    ~Descriptor() {
        if (fd >= 0) ::close(fd);
    }
};

/// Opens a regular file for reading (a FIFO is refused without waiting for a writer) and returns
/// its size; throws InputError("PATH: reason").
inline std::uint64_t open_regular(const std::string& path, Descriptor& d) {
    d.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (d.fd < 0) throw InputError(path + ": " + std::strerror(errno));
    struct stat st {};
    if (::fstat(d.fd, &st) != 0) throw InputError(path + ": " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw InputError(path + ": not a regular file");
    ::fcntl(d.fd, F_SETFL, ::fcntl(d.fd, F_GETFL) & ~O_NONBLOCK);
    return static_cast<std::uint64_t>(st.st_size);
}

/// Reads up to `count` bytes at `offset`; returns how many were read (fewer at the end of file).
inline std::size_t read_at(int fd, void* out, std::size_t count, std::uint64_t offset) {
    std::size_t got = 0;
    while (got < count) {
        const ssize_t n = ::pread(fd, static_cast<char*>(out) + got, count - got, static_cast<off_t>(offset + got));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        got += static_cast<std::size_t>(n);
    }
    return got;
}

}  // namespace caustica::io
