// Named cameras per scene ("camera bookmarks"), kept between runs in one small text file that
// every preview of the user shares (docs/PREVIEW.md, "What you see is what you save").
#pragma once

#include "core/scene/scene_desc.h"

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace caustica::ui {

/// The bookmarks file is read up to this size: a larger one is read only this far and never
/// written over.
inline constexpr std::size_t bookmarks_read_limit = 1u << 20;
/// The bookmarks file is written up to this size, well under the read limit: the newest lines
/// that fit are kept, the oldest dropped (with a warning).
inline constexpr std::size_t bookmarks_write_limit = bookmarks_read_limit / 2;
/// How long a change waits for another preview's change of the file to finish.
inline constexpr double bookmarks_lock_wait_seconds = 2.0;

/// The bookmarks file holds one bookmark a line, "SCENE<TAB>NAME<TAB>ex ey ez vx vy vz ux uy uz
/// fov" (tab, line breaks and backslash in SCENE and NAME escaped as \t \n \r \\). Each change
/// takes the lock file beside it (FILE.lock), re-reads the file, changes only its own bookmark
/// (two previews keep each other's), replaces the file atomically and lets the lock go; if the
/// lock is not had within the wait, nothing changes and warning() says so. The file is written up
/// to bookmarks_write_limit. A line that cannot be read is skipped with a warning and written back
/// as it was; a file over bookmarks_read_limit is read that far and never written over; one that
/// is not a regular file is ignored and never written over.
class CameraBookmarks {
public:
    /// Reads `file` ("" = kept in memory only); a change waits at most `lock_wait_seconds` for
    /// the lock.
    explicit CameraBookmarks(std::string file, double lock_wait_seconds = bookmarks_lock_wait_seconds);
    /// The bookmarks of `scene` (absolute path), in the order they were made.
    std::vector<std::pair<std::string, CameraDesc>> of(const std::string& scene) const;
    /// Adds or replaces the bookmark `name` of `scene` and writes the file. Tabs and line breaks in
    /// the name become spaces. False when nothing was made: an empty name, or the file's lock not
    /// had in time (warning() says so).
    bool set(const std::string& scene, std::string name, const CameraDesc& camera);
    /// Removes a bookmark and writes the file (nothing is removed if the lock is not had in time).
    void remove(const std::string& scene, const std::string& name);
    /// What went wrong reading or writing the file, or what the last save dropped ("" = nothing).
    const std::string& warning() const { return warning_; }

private:
    struct Entry {
        std::string scene, name;
        CameraDesc camera;
        std::string raw;  ///< an unreadable line, kept verbatim ("" = a bookmark)
    };
    /// How far the file was read.
    enum class Read {
        whole,     ///< all of it: it may be written back
        start,     ///< over the read limit: its first lines only, never written over
        refused,   ///< not a regular file or not readable: nothing
    };
    /// Reads the file into `entries` (warning_ says what was wrong with it).
    Read read(std::vector<Entry>& entries);
    /// Sets (camera given) or removes one bookmark, merged into the file as it is now; false when
    /// the lock was not had (then nothing changed).
    bool change(const std::string& scene, const std::string& name, const CameraDesc* camera);
    /// Writes `entries_`, the newest lines that fit in bookmarks_write_limit (the others are
    /// dropped from `entries_` too, with a warning).
    void write();
    std::string file_, warning_;
    double lock_wait_seconds_;
    std::vector<Entry> entries_;
};

/// Where the bookmarks are kept: "camera-bookmarks" beside the recent list ("" when that is "").
std::string bookmarks_file_beside(const std::string& recent_file);

}  // namespace caustica::ui
