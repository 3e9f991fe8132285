#include "ui/scene_source.h"

#include "core/scene/source_location.h"
#include "ui/small_file.h"

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <cstdlib>
#include <set>

namespace caustica::ui {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t recent_length = 10;

double now_seconds() {
    using clock = std::chrono::steady_clock;
    return std::chrono::duration<double>(clock::now().time_since_epoch()).count();
}

LoadedScene load(const std::string& path, const LoadSettings& settings) {
    LoadedScene loaded;
    loaded.path = path;
    try {
        if (!fs::is_regular_file(path)) throw InputError(not_a_scene_file(path));
        loaded.script = load_scene_script(path, settings);
        if (loaded.script.renders.empty())
            throw InputError(path + ": the script calls no gr.render; nothing to show");
    } catch (const ScriptCancelled&) {
        loaded.error = path + ": loading interrupted";
    } catch (const std::exception& e) {
        loaded.error = e.what();
    }
    return loaded;
}

std::string absolute_path(const std::string& path) {
    std::error_code ec;
    const fs::path p = fs::weakly_canonical(fs::absolute(path), ec);
    return ec ? path : p.string();
}

/// A file's size; 0 for a folder (watched for files created in it) or what cannot be read.
std::uintmax_t size_of(const fs::path& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) return 0;
    const std::uintmax_t size = fs::file_size(path, ec);
    return ec ? 0 : size;
}

}  // namespace

std::string not_a_scene_file(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    switch (st.type()) {
        case fs::file_type::directory: return path + ": is a folder, not a scene file";
        case fs::file_type::fifo: return path + ": is a named pipe (FIFO), not a scene file";
        case fs::file_type::block:
        case fs::file_type::character: return path + ": is a device, not a scene file";
        case fs::file_type::socket: return path + ": is a socket, not a scene file";
        case fs::file_type::not_found: return path + ": no such scene file";
        default: return path + ": cannot be read as a scene file" + (ec ? " (" + ec.message() + ")" : std::string());
    }
}

SceneSource::SceneSource(LoadSettings settings, std::string recent_file)
    : settings_(std::move(settings)), recent_file_(std::move(recent_file)) {
    settings_.cancel = &stop_;
    if (recent_file_.empty()) return;
    const SmallFile file = read_small_file(recent_file_, recent_file_limit);
    if (!file.problem.empty()) {
        // Never written over either: it may be something the person keeps there on purpose.
        warning_ = recent_file_ + ": " + file.problem + "; the recent scenes list is not read or kept";
        recent_writable_ = false;
        std::fprintf(stderr, "caustica view: warning: %s\n", warning_.c_str());
        return;
    }
    std::size_t start = 0;
    while (start < file.text.size() && recent_.size() < recent_length) {
        std::size_t end = file.text.find('\n', start);
        if (end == std::string::npos) end = file.text.size();
        const std::string line = file.text.substr(start, end - start);
        // A path longer than any the system accepts is not a path (PATH_MAX is 4096).
        if (!line.empty() && line.size() < 4096 && line.find('\0') == std::string::npos) recent_.push_back(line);
        start = end + 1;
    }
}

SceneSource::~SceneSource() {
    stop_ = true;  // the Lua hook stops running scripts promptly
    for (InFlight& f : in_flight_) f.result.wait();
}

void SceneSource::open(const std::string& path) {
    const std::uint64_t id = ++latest_;
    in_flight_.push_back({id, std::async(std::launch::async, load, path, settings_)});
}

std::optional<LoadedScene> SceneSource::poll() {
    std::optional<LoadedScene> newest;
    for (auto it = in_flight_.begin(); it != in_flight_.end();) {
        if (it->result.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
            ++it;
            continue;
        }
        LoadedScene loaded = it->result.get();
        if (it->id == latest_) newest = std::move(loaded);  // superseded loads are dropped
        it = in_flight_.erase(it);
    }
    return newest;
}

void SceneSource::watch(const std::string& script, const std::vector<std::string>& dependencies) {
    watched_.clear();
    std::vector<std::string> files = dependencies;
    files.insert(files.begin(), script);
    for (const std::string& f : files) {
        std::error_code ec;
        Watched w{f, fs::last_write_time(f, ec), 0};
        if (ec) continue;
        w.size = size_of(f);
        watched_.push_back(w);
    }
    checked_at_ = now_seconds();
}

bool SceneSource::changed_on_disk() {
    const double now = now_seconds();
    if (now - checked_at_ < 0.25) return false;
    checked_at_ = now;
    for (const Watched& w : watched_) {
        std::error_code ec;
        const auto time = fs::last_write_time(w.path, ec);
        if (ec) continue;  // being replaced by an editor: look again next time
        if (time != w.time || size_of(w.path) != w.size) return true;
    }
    return false;
}

void SceneSource::add_recent(const std::string& path) {
    const std::string p = absolute_path(path);
    recent_.erase(std::remove(recent_.begin(), recent_.end(), p), recent_.end());
    recent_.insert(recent_.begin(), p);
    if (recent_.size() > recent_length) recent_.resize(recent_length);
    if (recent_file_.empty() || !recent_writable_) return;
    std::string text;
    for (const std::string& r : recent_)
        if (r.find('\n') == std::string::npos) text += r + '\n';  // a line break would split the entry
    if (const std::string problem = write_atomically(recent_file_, text); !problem.empty())
        warning_ = recent_file_ + ": cannot write the recent scenes list (" + problem + ")";
}

std::vector<std::string> SceneSource::scene_files(const std::string& current) const {
    std::set<std::string> files;
    auto scan = [&](const fs::path& folder, int depth) {
        std::error_code ec;
        if (!fs::is_directory(folder, ec)) return;
        fs::recursive_directory_iterator it(folder, fs::directory_options::skip_permission_denied, ec), end;
        for (; !ec && it != end; it.increment(ec)) {
            if (it.depth() > depth) {
                it.disable_recursion_pending();
                continue;
            }
            if (it->is_regular_file(ec) && it->path().extension() == ".lua")
                files.insert(it->path().lexically_normal().string());
        }
    };
    scan("scenes", 1);
    if (!current.empty()) scan(fs::path(current).parent_path().empty() ? fs::path(".") : fs::path(current).parent_path(), 0);
    return {files.begin(), files.end()};
}

std::string default_recent_file() {
    if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg)
        return (fs::path(xdg) / "caustica" / "recent-scenes").string();
    if (const char* home = std::getenv("HOME"); home && *home)
        return (fs::path(home) / ".config" / "caustica" / "recent-scenes").string();
    return {};
}

}  // namespace caustica::ui
