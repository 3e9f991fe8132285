// Where an output file may land. The user's own names (-o, a name typed in the preview) go
// anywhere; a scene's own (gr.render's file names) only into the current folder or below it,
// judged on the real file system: the folder is opened first and the opened folder's real path
// (/proc/self/fd) is checked, and the write then goes through that open folder, so no symlink,
// `..` or later rename of a name on the way can carry it elsewhere (docs/RELIABILITY.md, section 1).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

namespace caustica {

/// Who chose an output's name, and so where it may land.
enum class OutputPlace {
    anywhere,               ///< the user's name: -o, or one typed in the preview
    inside_current_folder,  ///< a scene's gr.render name: its real folder is the current folder or below it
};

/// Thrown when an output of OutputPlace::inside_current_folder would land outside the current
/// folder; nothing was written. The message reads "'NAME' leads to 'REAL', outside the current
/// folder 'CWD'": callers add the gr.render location.
class OutputOutsideFolder : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// The folder an output is written into, open for the *at calls (openat, renameat, unlinkat):
/// what is written lands in the folder that was checked, whatever its name leads to afterwards.
class OutputFolder {
public:
    /// Opens the folder of `target` (an absolute path; `shown` is its name for messages). For
    /// OutputPlace::inside_current_folder, throws OutputOutsideFolder when the opened folder's real
    /// path is not the current folder's or below it, or when the name itself is a symlink to a file
    /// outside it. When the folder cannot be opened, ok() is false and error() holds the errno.
    OutputFolder(const std::filesystem::path& target, OutputPlace place, const std::string& shown);
    ~OutputFolder();
    OutputFolder(const OutputFolder&) = delete;
    OutputFolder& operator=(const OutputFolder&) = delete;

    bool ok() const { return fd_ >= 0; }
    int error() const { return error_; }
    /// The open folder (O_PATH), for the *at calls.
    int fd() const { return fd_; }
    /// The folder's path: its real path when it was checked, else as named.
    const std::filesystem::path& path() const { return path_; }

private:
    int fd_ = -1;
    int error_ = 0;
    std::filesystem::path path_;
};

/// Checks, without writing anything, that `path` would land inside the current folder as an
/// OutputPlace::inside_current_folder write checks it: "" when it would (or when its folder
/// cannot be opened: the write says why), else the message of OutputOutsideFolder.
std::string output_outside_current_folder(const std::string& path);

}  // namespace caustica
