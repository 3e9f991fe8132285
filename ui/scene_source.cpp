#include "ui/scene_source.h"

#include "core/scene/source_location.h"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
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
        if (!fs::is_regular_file(path)) throw InputError(path + ": no such scene file");
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

}  // namespace

SceneSource::SceneSource(LoadSettings settings, std::string recent_file)
    : settings_(std::move(settings)), recent_file_(std::move(recent_file)) {
    settings_.cancel = &stop_;
    if (recent_file_.empty()) return;
    std::ifstream in(recent_file_);
    for (std::string line; std::getline(in, line) && recent_.size() < recent_length;)
        if (!line.empty()) recent_.push_back(line);
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
        w.size = fs::file_size(f, ec);
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
        const auto size = fs::file_size(w.path, ec);
        if (!ec && (time != w.time || size != w.size)) return true;
    }
    return false;
}

void SceneSource::add_recent(const std::string& path) {
    const std::string p = absolute_path(path);
    recent_.erase(std::remove(recent_.begin(), recent_.end(), p), recent_.end());
    recent_.insert(recent_.begin(), p);
    if (recent_.size() > recent_length) recent_.resize(recent_length);
    if (recent_file_.empty()) return;
    std::error_code ec;
    fs::create_directories(fs::path(recent_file_).parent_path(), ec);
    std::ofstream out(recent_file_, std::ios::trunc);
    for (const std::string& r : recent_) out << r << '\n';
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
