// Atomic output for every format the renderer writes (PNG, OpenEXR, PFM): a hidden temporary
// beside the target, renamed over it only when whole, so that a failed, cancelled or interrupted
// write never leaves a truncated file or loses the one that was there; the temporaries of a write
// in progress are removed by a signal handler, those of killed runs by the next write. The
// temporary is made and renamed through the open folder (core/io/output_folder.h), so a scene's
// output lands in the folder that was checked.
#pragma once

#include "core/io/output_folder.h"

#include <atomic>
#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>

namespace caustica {

/// Thrown by write_file_atomic (and the PNG, EXR and PFM writers built on it) when
/// its cancel flag was raised; the temporary is already removed and nothing was written at the path.
class ImageWriteCancelled : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// What a file body writer reports to write_file_atomic.
enum class FileWriteOutcome { written, failed, cancelled };

/// Writes a whole file's bytes to `file` (a fresh temporary); on `failed` sets `error` to the
/// reason. It may also throw: write_file_atomic then removes the temporary and rethrows.
using FileWriteBody = std::function<FileWriteOutcome(std::FILE* file, std::string& error)>;

/// Writes `path` atomically, whatever its format: opens its folder (checked for `place`: a scene's
/// name must lead inside the current folder, else OutputOutsideFolder and nothing is written),
/// removes stale temporaries of killed runs from it, creates a hidden temporary
/// ".NAME.caustica-tmp-HOST-PID-N" there (published for
/// remove_output_temporaries_from_signal_handler), runs `body` on it, flushes, fsyncs and renames
/// it over NAME. A failure or `cancel` (checked again before the rename) removes the temporary:
/// std::runtime_error "cannot write 'PATH': reason", or ImageWriteCancelled.
void write_file_atomic(const std::string& path, const FileWriteBody& body, const std::atomic<bool>* cancel = nullptr,
                       OutputPlace place = OutputPlace::anywhere);

/// Checks, without writing anything, that write_file_atomic could write `path`: its folder takes
/// a new file (a temporary is created and removed at once, which also catches a read-only file
/// system, or a folder root may not write to), `path` is not a folder and its name is not too
/// long. Returns "" or the reason ("No such file or directory", "it is a folder", ...).
std::string output_file_problem(const std::string& path);

/// Unlinks the temporaries of the writes in progress (every write_file_atomic). Async-signal-safe:
/// for a signal handler that is about to end the process (a second Ctrl-C), so that no temporary survives it.
void remove_output_temporaries_from_signal_handler() noexcept;

/// Removes, from `folder`, the temporaries of write_file_atomic whose writing process no longer
/// exists: files named ".NAME.caustica-tmp-HOST-PID-N" (or "-probe-", from
/// output_file_problem) owned by this user, HOST this machine and PID not running.
/// Returns how many were removed; errors are ignored (the folder may be unreadable).
int remove_stale_output_temporaries(const std::string& folder);

}  // namespace caustica
