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

/// The default place of the recent list: $XDG_CONFIG_HOME/caustica/recent-scenes, else
/// ~/.config/caustica/recent-scenes ("" when neither is known).
std::string default_recent_file();

}  // namespace caustica::ui
