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

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

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

/// Writes `text` to `file` through a temporary beside it (named with the process id and a counter,
/// so two previews never share one) renamed over it: a reader sees the old file or the new one.
/// "" on success, else why not.
std::string write_atomically(const std::string& file, const std::string& text) {
    static std::atomic<unsigned> counter{0};
    std::error_code ec;
    fs::create_directories(fs::path(file).parent_path(), ec);
    const std::string temporary =
        file + ".tmp." + std::to_string(static_cast<long>(::getpid())) + "." + std::to_string(counter++);
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) return std::strerror(errno);
    std::size_t done = 0;
    std::string problem;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            problem = std::strerror(errno);
            break;
        }
        done += static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0 && problem.empty()) problem = std::strerror(errno);
    if (problem.empty()) {
        fs::rename(temporary, file, ec);
        if (ec) problem = ec.message();
    }
    if (!problem.empty()) fs::remove(temporary, ec);
    return problem;
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

SmallFile read_small_file(const std::string& path, std::size_t limit) {
    SmallFile result;
    // O_NONBLOCK: opening a FIFO must not wait for a writer; the type is checked on the open file
    // (fstat), so it cannot be swapped between the check and the read.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        if (errno == ENOENT) return result;  // missing: nothing to read, fine to create
        result.exists = true;
        result.problem = std::string("cannot be opened (") + std::strerror(errno) + ")";
        return result;
    }
    result.exists = true;
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        result.problem = std::string("cannot be read (") + std::strerror(errno) + ")";
    } else if (S_ISDIR(st.st_mode)) {
        result.problem = "is a folder, not a file";
    } else if (S_ISFIFO(st.st_mode)) {
        result.problem = "is a named pipe (FIFO), not a regular file";
    } else if (!S_ISREG(st.st_mode)) {
        result.problem = "is a device or socket, not a regular file";
    } else if (static_cast<std::uintmax_t>(st.st_size) > limit) {
        result.problem = "larger than " + std::to_string(limit >> 20) + " MiB";
    } else {
        std::string text(limit + 1, '\0');  // one more byte tells a file that grew past the limit
        std::size_t got = 0;
        while (got < text.size()) {
            const ssize_t n = ::read(fd, text.data() + got, text.size() - got);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0) {
                result.problem = std::string("cannot be read (") + std::strerror(errno) + ")";
                break;
            }
            if (n == 0) break;
            got += static_cast<std::size_t>(n);
        }
        if (result.problem.empty() && got > limit) result.problem = "larger than " + std::to_string(limit >> 20) + " MiB";
        if (result.problem.empty()) {
            text.resize(got);
            result.text = std::move(text);
        }
    }
    ::close(fd);
    return result;
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

/// A field of the bookmarks file: tab, line breaks and backslash written as \t \n \r \\ so that
/// any scene path stays on its line.
std::string escape_field(const std::string& text) {
    std::string out;
    for (const char c : text) {
        if (c == '\\') out += "\\\\";
        else if (c == '\t') out += "\\t";
        else if (c == '\n') out += "\\n";
        else if (c == '\r') out += "\\r";
        else out += c;
    }
    return out;
}

std::string unescape_field(const std::string& text) {
    std::string out;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '\\' || i + 1 == text.size()) {
            out += text[i];
            continue;
        }
        const char next = text[i + 1];
        if (next == '\\') out += '\\';
        else if (next == 't') out += '\t';
        else if (next == 'n') out += '\n';
        else if (next == 'r') out += '\r';
        else {
            out += '\\';  // not an escape we write: keep it as it is
            continue;
        }
        ++i;
    }
    return out;
}

}  // namespace

CameraBookmarks::CameraBookmarks(std::string file) : file_(std::move(file)) {
    if (file_.empty()) return;
    if (!read(entries_)) warning_ += "; camera bookmarks ignored";
}

bool CameraBookmarks::read(std::vector<Entry>& entries) {
    entries.clear();
    warning_.clear();
    const SmallFile file = read_small_file(file_, 1u << 20);
    if (!file.problem.empty()) {
        warning_ = file_ + ": " + file.problem;
        return false;
    }
    int line_number = 0, bad = 0, first_bad = 0;
    std::size_t start = 0;
    while (start < file.text.size()) {
        std::size_t stop = file.text.find('\n', start);
        if (stop == std::string::npos) stop = file.text.size();
        const std::string line = file.text.substr(start, stop - start);
        start = stop + 1;
        ++line_number;
        if (line.empty()) continue;
        const std::size_t a = line.find('\t'), b = a == std::string::npos ? a : line.find('\t', a + 1);
        Entry e;
        if (b == std::string::npos || a == 0 || b == a + 1 || !parse_camera(line.substr(b + 1), e.camera)) {
            // Kept verbatim and written back: a hand edit gone wrong is the person's to repair.
            if (bad++ == 0) first_bad = line_number;
            e.raw = line;
            entries.push_back(std::move(e));
            continue;
        }
        e.scene = unescape_field(line.substr(0, a));
        e.name = unescape_field(line.substr(a + 1, b - a - 1));
        entries.push_back(std::move(e));
    }
    if (bad > 0)
        warning_ = file_ + ": " + std::to_string(bad) + " unreadable line" + (bad == 1 ? "" : "s") +
                   " ignored (kept in the file as " + (bad == 1 ? "it is" : "they are") + "; first: line " +
                   std::to_string(first_bad) + ")";
    return true;
}

std::vector<std::pair<std::string, CameraDesc>> CameraBookmarks::of(const std::string& scene) const {
    std::vector<std::pair<std::string, CameraDesc>> found;
    for (const Entry& e : entries_)
        if (e.raw.empty() && e.scene == scene) found.emplace_back(e.name, e.camera);
    return found;
}

bool CameraBookmarks::set(const std::string& scene, std::string name, const CameraDesc& camera) {
    for (char& c : name)
        if (c == '\t' || c == '\n' || c == '\r') c = ' ';
    if (name.find_first_not_of(' ') == std::string::npos) return false;
    change(scene, name, &camera);
    return true;
}

void CameraBookmarks::remove(const std::string& scene, const std::string& name) {
    change(scene, name, nullptr);
}

void CameraBookmarks::change(const std::string& scene, const std::string& name, const CameraDesc* camera) {
    auto apply = [&](std::vector<Entry>& entries) {
        auto same = [&](const Entry& e) { return e.raw.empty() && e.scene == scene && e.name == name; };
        if (!camera) {
            const auto before = entries.size();
            std::erase_if(entries, same);
            return entries.size() != before;
        }
        auto it = std::find_if(entries.begin(), entries.end(), same);
        if (it != entries.end()) it->camera = *camera;
        else entries.push_back({scene, name, *camera, {}});
        return true;
    };
    if (file_.empty()) {
        apply(entries_);
        return;
    }
    // Another preview may have changed the file since we read it: start from what is there now
    // and change only this one bookmark, so neither window loses the other's.
    std::vector<Entry> current;
    if (!read(current)) {
        apply(entries_);  // kept for this session
        warning_ += "; it was not read, so it is not written over either: this bookmark lasts until the preview closes";
        return;
    }
    const bool changed = apply(current);
    entries_ = std::move(current);
    if (!changed) return;
    std::string text;
    for (const Entry& e : entries_) {
        if (!e.raw.empty()) {
            text += e.raw + '\n';
            continue;
        }
        const CameraDesc& c = e.camera;
        text += escape_field(e.scene) + '\t' + escape_field(e.name) + '\t' + number(c.eye.x) + ' ' + number(c.eye.y) + ' ' +
                number(c.eye.z) + ' ' + number(c.view.x) + ' ' + number(c.view.y) + ' ' + number(c.view.z) + ' ' +
                number(c.up.x) + ' ' + number(c.up.y) + ' ' + number(c.up.z) + ' ' + number(c.fovy_degrees) + '\n';
    }
    if (const std::string problem = write_atomically(file_, text); !problem.empty())
        warning_ = file_ + ": cannot write the camera bookmarks (" + problem + ")";
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
