// The small files the preview keeps between runs (the recent scenes list, the camera bookmarks,
// the integrator chosen per scene): read only when they are small regular files, replaced
// atomically, and changed under an advisory lock when several previews share them.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace caustica::ui {

/// A small text file read whole (see read_small_file).
struct SmallFile {
    bool exists = false;      ///< false: no such file (nothing read, nothing wrong)
    bool over_limit = false;  ///< a regular file larger than the limit (problem says so)
    std::string text;         ///< the contents when problem is empty; the first `limit` bytes of a
                              ///< file over the limit when OverLimit::read_start asked for them
    std::string problem;      ///< why it was not read: "is a named pipe (FIFO), ...", "larger than 1 MiB", ...
};

/// What read_small_file does with a regular file larger than its limit.
enum class OverLimit {
    refuse,      ///< read nothing
    read_start,  ///< read its first `limit` bytes (the caller decides what a cut last line means)
};

/// Reads `path` only if it is a regular file of at most `limit` bytes: a FIFO, device (a link to
/// /dev/zero), folder or oversized file is refused at once, without waiting or reading it (an
/// oversized one is read up to `limit` bytes if `over` asks for it).
SmallFile read_small_file(const std::string& path, std::size_t limit, OverLimit over = OverLimit::refuse);

/// Writes `text` to `file` through a temporary beside it (named with the process id and a counter,
/// so two previews never share one) renamed over it: a reader sees the old file or the new one.
/// The folder is created if missing. "" on success, else why not.
std::string write_atomically(const std::string& file, const std::string& text);

/// A field of a tab-separated line: tab, line breaks and backslash written as \t \n \r \\ so that
/// any text (a scene path) stays on its line and in its field.
std::string escape_field(const std::string& text);
/// The text of a field escape_field wrote (a backslash that starts no escape stays as it is).
std::string unescape_field(const std::string& text);

/// What write_newest_lines wrote.
struct LinesWritten {
    std::vector<bool> kept;   ///< per line: whether it is in the file
    std::size_t dropped = 0;  ///< the lines left out
    std::string problem;      ///< why the file could not be written ("" = written)
};

/// Writes `lines` (oldest first, each without its line break) to `file` with write_atomically,
/// keeping it within `limit` bytes: from the newest back, each line that still fits.
LinesWritten write_newest_lines(const std::string& file, const std::vector<std::string>& lines, std::size_t limit);

/// Keeps the elements of `items` whose flag in `kept` is set (write_newest_lines' `kept`), in order.
template <class T>
void keep_flagged(std::vector<T>& items, const std::vector<bool>& kept) {
    std::size_t next = 0;
    for (std::size_t i = 0; i < items.size(); ++i) {
        if (!kept[i]) continue;
        if (next != i) items[next] = std::move(items[i]);  // never moved onto itself
        ++next;
    }
    items.resize(next);
}

/// An exclusive advisory lock (flock) on a lock file, held while the object lives: it makes the
/// read, change and atomic rewrite of a file that several previews share one step, so that no
/// preview writes back a file another one changed after it was read. flock locks belong to the
/// open file, so two threads of one process exclude each other too.
class FileLock {
public:
    /// Opens (creating it and its folder if missing) and locks `lock_file`, trying again for at
    /// most `wait_seconds` while another process holds it; held() tells whether it was had.
    FileLock(const std::string& lock_file, double wait_seconds);
    /// Releases the lock (the lock file stays: removing it would let two processes lock two files).
    ~FileLock();
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;

    bool held() const { return fd_ >= 0; }
    /// Why the lock was not had: "still held by another process after 2 s", "cannot be opened
    /// (Permission denied)", ... ("" when held).
    const std::string& problem() const { return problem_; }

private:
    int fd_ = -1;
    std::string problem_;
};

}  // namespace caustica::ui
