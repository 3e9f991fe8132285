#include "ui/scene_source.h"

#include "core/scene/source_location.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
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

/// A file's size; 0 for a folder (watched for files created in it) or what cannot be read.
std::uintmax_t size_of(const fs::path& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) return 0;
    const std::uintmax_t size = fs::file_size(path, ec);
    return ec ? 0 : size;
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

// --- camera bookmarks

namespace {

std::string number(double v) {
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", v);
    return text;
}

/// Reads "ex ey ez vx vy vz ux uy uz fov"; false unless all ten are finite, view and up are not
/// zero and the angle lies in (0, 180).
bool parse_camera(const std::string& text, CameraDesc& camera) {
    double v[10];
    const char* p = text.data();
    const char* end = text.data() + text.size();
    for (double& x : v) {
        while (p < end && *p == ' ') ++p;
        const auto [next, ec] = std::from_chars(p, end, x);
        if (ec != std::errc() || !std::isfinite(x)) return false;
        p = next;
    }
    while (p < end && *p == ' ') ++p;
    if (p != end) return false;
    camera.eye = {v[0], v[1], v[2]};
    camera.view = {v[3], v[4], v[5]};
    camera.up = {v[6], v[7], v[8]};
    camera.fovy_degrees = v[9];
    return glm::length(camera.view) > 0.0 && glm::length(camera.up) > 0.0 && v[9] > 0.0 && v[9] < 180.0;
}

}  // namespace

CameraBookmarks::CameraBookmarks(std::string file) : file_(std::move(file)) {
    if (file_.empty()) return;
    std::error_code ec;
    if (!fs::exists(file_, ec)) return;
    const std::uintmax_t size = fs::file_size(file_, ec);
    if (ec || size > (1u << 20)) {
        warning_ = file_ + ": " + (ec ? "cannot be read" : "larger than 1 MiB") + "; camera bookmarks ignored";
        return;
    }
    std::ifstream in(file_);
    int line_number = 0, bad = 0, first_bad = 0;
    for (std::string line; std::getline(in, line);) {
        ++line_number;
        if (line.empty()) continue;
        const std::size_t a = line.find('\t'), b = a == std::string::npos ? a : line.find('\t', a + 1);
        Entry e;
        if (b == std::string::npos || a == 0 || b == a + 1 || !parse_camera(line.substr(b + 1), e.camera)) {
            if (bad++ == 0) first_bad = line_number;
            continue;
        }
        e.scene = line.substr(0, a);
        e.name = line.substr(a + 1, b - a - 1);
        entries_.push_back(std::move(e));
    }
    if (bad > 0)
        warning_ = file_ + ": " + std::to_string(bad) + " unreadable line" + (bad == 1 ? "" : "s") + " ignored (first: line " +
                   std::to_string(first_bad) + ")";
}

std::vector<std::pair<std::string, CameraDesc>> CameraBookmarks::of(const std::string& scene) const {
    std::vector<std::pair<std::string, CameraDesc>> found;
    for (const Entry& e : entries_)
        if (e.scene == scene) found.emplace_back(e.name, e.camera);
    return found;
}

bool CameraBookmarks::set(const std::string& scene, std::string name, const CameraDesc& camera) {
    for (char& c : name)
        if (c == '\t' || c == '\n' || c == '\r') c = ' ';
    if (name.find_first_not_of(' ') == std::string::npos) return false;
    auto it = std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.scene == scene && e.name == name; });
    if (it != entries_.end()) it->camera = camera;
    else entries_.push_back({scene, name, camera});
    write();
    return true;
}

void CameraBookmarks::remove(const std::string& scene, const std::string& name) {
    const auto before = entries_.size();
    std::erase_if(entries_, [&](const Entry& e) { return e.scene == scene && e.name == name; });
    if (entries_.size() != before) write();
}

void CameraBookmarks::write() {
    if (file_.empty()) return;
    std::error_code ec;
    fs::create_directories(fs::path(file_).parent_path(), ec);
    const std::string temporary = file_ + ".tmp";
    {
        std::ofstream out(temporary, std::ios::trunc);
        for (const Entry& e : entries_) {
            const CameraDesc& c = e.camera;
            out << e.scene << '\t' << e.name << '\t' << number(c.eye.x) << ' ' << number(c.eye.y) << ' ' << number(c.eye.z)
                << ' ' << number(c.view.x) << ' ' << number(c.view.y) << ' ' << number(c.view.z) << ' ' << number(c.up.x)
                << ' ' << number(c.up.y) << ' ' << number(c.up.z) << ' ' << number(c.fovy_degrees) << '\n';
        }
        if (!out.flush()) {
            warning_ = file_ + ": cannot write the camera bookmarks";
            fs::remove(temporary, ec);
            return;
        }
    }
    fs::rename(temporary, file_, ec);  // atomic: a reader sees the old file or the new one
    if (ec) warning_ = file_ + ": cannot write the camera bookmarks (" + ec.message() + ")";
}

std::string bookmarks_file_beside(const std::string& recent_file) {
    if (recent_file.empty()) return {};
    return (fs::path(recent_file).parent_path() / "camera-bookmarks").string();
}

std::string default_recent_file() {
    if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg)
        return (fs::path(xdg) / "caustica" / "recent-scenes").string();
    if (const char* home = std::getenv("HOME"); home && *home)
        return (fs::path(home) / ".config" / "caustica" / "recent-scenes").string();
    return {};
}

}  // namespace caustica::ui
