// Where the preview's scenes come from: scripts loaded on a background thread (the UI never
// waits for Lua), watched for changes on disk, the recently opened list and the scene folder.
#pragma once

#include "core/lua/scene_loader.h"

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <future>
#include <optional>
#include <string>
#include <vector>

namespace caustica::ui {

/// A small text file read whole (see read_small_file).
struct SmallFile {
    bool exists = false;  ///< false: no such file (nothing read, nothing wrong)
    std::string text;     ///< the contents when problem is empty
    std::string problem;  ///< why it was not read: "is a named pipe (FIFO), ...", "larger than 1 MiB", ...
};
/// Reads `path` only if it is a regular file of at most `limit` bytes: a FIFO, device (a link to
/// /dev/zero), folder or oversized file is refused at once, without waiting or reading it.
SmallFile read_small_file(const std::string& path, std::size_t limit);

/// The recent scenes list is ten paths; a bigger file is not ours.
inline constexpr std::size_t recent_file_limit = 1u << 20;

/// The message for a scene path that is not a regular file: "PATH: no such scene file", "PATH: is
/// a folder, not a scene file", ... (a FIFO, a device, a socket).
std::string not_a_scene_file(const std::string& path);

/// The outcome of loading one script.
struct LoadedScene {
    std::string path;    ///< as opened
    SceneScript script;  ///< valid when error is empty
    std::string error;   ///< "file:line: message" when the script failed
};

/// Loads scene scripts asynchronously and notices when the loaded files change.
class SceneSource {
public:
    /// `settings` limit each script run; `recent_file` keeps the recent list ("" = not kept).
    SceneSource(LoadSettings settings, std::string recent_file);
    /// Stops scripts still running and waits for them.
    ~SceneSource();
    SceneSource(const SceneSource&) = delete;
    SceneSource& operator=(const SceneSource&) = delete;

    /// Starts loading `path` in the background; a later open() supersedes it.
    void open(const std::string& path);
    /// The newest requested load, once it has finished (then nothing until the next open()).
    std::optional<LoadedScene> poll();
    /// Whether a requested load has not finished yet.
    bool loading() const { return !in_flight_.empty() && in_flight_.back().id == latest_; }

    /// Watches `script` and the files it read (meshes, textures) from their current state on; a
    /// folder among them counts as changed when a file is created, renamed or removed in it.
    void watch(const std::string& script, const std::vector<std::string>& dependencies);
    /// Whether a watched file changed since watch() (checked at most every quarter second).
    bool changed_on_disk();

    /// Recently opened scenes, newest first (absolute paths).
    const std::vector<std::string>& recent() const { return recent_; }
    /// Puts `path` at the front of the recent list (and saves the list, unless the file was
    /// refused at start: what we would not read we do not write over).
    void add_recent(const std::string& path);
    /// Why the recent list file was not read or written ("" = fine).
    const std::string& warning() const { return warning_; }

    /// The .lua files under ./scenes and beside `current`, sorted, without duplicates.
    std::vector<std::string> scene_files(const std::string& current) const;

private:
    struct InFlight {
        std::uint64_t id;
        std::future<LoadedScene> result;
    };
    struct Watched {
        std::filesystem::path path;
        std::filesystem::file_time_type time;
        std::uintmax_t size;
    };

    LoadSettings settings_;
    std::string recent_file_;
    std::vector<std::string> recent_;
    std::string warning_;
    bool recent_writable_ = true;
    std::vector<InFlight> in_flight_;
    std::uint64_t latest_ = 0;
    std::atomic<bool> stop_{false};
    std::vector<Watched> watched_;
    double checked_at_ = 0.0;
};

/// Named cameras per scene ("camera bookmarks"), kept between runs in a small text file: one
/// bookmark a line, "SCENE<TAB>NAME<TAB>ex ey ez vx vy vz ux uy uz fov" (tab, line breaks and
/// backslash in SCENE and NAME escaped as \t \n \r \\). Each change re-reads the file and changes
/// only its own bookmark (two previews keep each other's), then replaces the file atomically. A
/// line that cannot be read is skipped with a warning and written back as it was; a file that is
/// over 1 MiB or not a regular file is ignored and never written over.
class CameraBookmarks {
public:
    /// Reads `file` ("" = kept in memory only).
    explicit CameraBookmarks(std::string file);
    /// The bookmarks of `scene` (absolute path), in the order they were made.
    std::vector<std::pair<std::string, CameraDesc>> of(const std::string& scene) const;
    /// Adds or replaces the bookmark `name` of `scene` and writes the file. Tabs and line breaks in
    /// the name become spaces; an empty name is refused (false).
    bool set(const std::string& scene, std::string name, const CameraDesc& camera);
    /// Removes a bookmark and writes the file.
    void remove(const std::string& scene, const std::string& name);
    /// What went wrong reading or writing the file ("" = nothing).
    const std::string& warning() const { return warning_; }

private:
    struct Entry {
        std::string scene, name;
        CameraDesc camera;
        std::string raw;  ///< an unreadable line, kept verbatim ("" = a bookmark)
    };
    /// Reads the file into `entries`; false (warning_ says why) when it is refused.
    bool read(std::vector<Entry>& entries);
    /// Sets (camera given) or removes one bookmark, merged into the file as it is now.
    void change(const std::string& scene, const std::string& name, const CameraDesc* camera);
    std::string file_, warning_;
    std::vector<Entry> entries_;
};

/// Where the bookmarks are kept: "camera-bookmarks" beside the recent list ("" when that is "").
std::string bookmarks_file_beside(const std::string& recent_file);

/// The default place of the recent list: $XDG_CONFIG_HOME/caustica/recent-scenes, else
/// ~/.config/caustica/recent-scenes ("" when neither is known).
std::string default_recent_file();

}  // namespace caustica::ui
