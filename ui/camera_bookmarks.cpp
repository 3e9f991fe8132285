#include "ui/camera_bookmarks.h"

#include "ui/small_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string_view>

namespace caustica::ui {
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

/// One line of the bookmarks file, without its line break.
std::string bookmark_line(const std::string& scene, const std::string& name, const CameraDesc& c) {
    return escape_field(scene) + '\t' + escape_field(name) + '\t' + number(c.eye.x) + ' ' + number(c.eye.y) + ' ' +
           number(c.eye.z) + ' ' + number(c.view.x) + ' ' + number(c.view.y) + ' ' + number(c.view.z) + ' ' +
           number(c.up.x) + ' ' + number(c.up.y) + ' ' + number(c.up.z) + ' ' + number(c.fovy_degrees);
}

/// `warning` followed by `more` ("; " between them when both are there).
void add_warning(std::string& warning, const std::string& more) {
    warning += (warning.empty() ? "" : "; ") + more;
}

}  // namespace

CameraBookmarks::CameraBookmarks(std::string file, double lock_wait_seconds)
    : file_(std::move(file)), lock_wait_seconds_(lock_wait_seconds) {
    if (file_.empty()) return;
    if (read(entries_) == Read::refused) warning_ += "; camera bookmarks ignored";
}

CameraBookmarks::Read CameraBookmarks::read(std::vector<Entry>& entries) {
    entries.clear();
    warning_.clear();
    const SmallFile file = read_small_file(file_, bookmarks_read_limit, OverLimit::read_start);
    if (!file.problem.empty() && !file.over_limit) {
        warning_ = file_ + ": " + file.problem;
        return Read::refused;
    }
    std::string_view text = file.text;
    if (file.over_limit) {
        // The last line was cut where the reading stopped: it is not a bookmark.
        const std::size_t last_break = text.rfind('\n');
        text = last_break == std::string_view::npos ? std::string_view() : text.substr(0, last_break + 1);
    }
    int line_number = 0, bad = 0, first_bad = 0;
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t stop = text.find('\n', start);
        if (stop == std::string_view::npos) stop = text.size();
        const std::string line(text.substr(start, stop - start));
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
    if (!file.over_limit) return Read::whole;
    // Written over, the lines past the limit would be lost: the person trims the file.
    add_warning(warning_, file_ + ": " + file.problem + "; only the bookmarks in its first " +
                              std::to_string(bookmarks_read_limit >> 20) +
                              " MiB are read, and it is never written over (remove old lines by hand to save new ones)");
    return Read::start;
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
    return change(scene, name, &camera);
}

void CameraBookmarks::remove(const std::string& scene, const std::string& name) {
    change(scene, name, nullptr);
}

bool CameraBookmarks::change(const std::string& scene, const std::string& name, const CameraDesc* camera) {
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
        return true;
    }
    // Another preview may change the file at the same time: under the lock, start from what is
    // there now and change only this one bookmark, so neither window loses the other's.
    const FileLock lock(file_ + ".lock", lock_wait_seconds_);
    if (!lock.held()) {
        // Made only in this window, it would vanish at the next save, which starts from the file.
        warning_ = file_ + ".lock: " + lock.problem() + "; the camera bookmarks were not changed (try again)";
        return false;
    }
    std::vector<Entry> current;
    switch (read(current)) {
        case Read::refused:
            apply(entries_);  // kept for this session
            warning_ += "; it was not read, so it is not written over either: this change lasts until the preview closes";
            return true;
        case Read::start:
            apply(entries_);
            warning_ += "; this change lasts until the preview closes";
            return true;
        case Read::whole: break;
    }
    const bool changed = apply(current);
    entries_ = std::move(current);
    if (changed) write();
    return true;
}

void CameraBookmarks::write() {
    std::vector<std::string> lines;
    lines.reserve(entries_.size());
    for (const Entry& e : entries_) lines.push_back(e.raw.empty() ? bookmark_line(e.scene, e.name, e.camera) : e.raw);
    const LinesWritten written = write_newest_lines(file_, lines, bookmarks_write_limit);
    keep_flagged(entries_, written.kept);
    if (!written.problem.empty()) {
        warning_ = file_ + ": cannot write the camera bookmarks (" + written.problem + ")";
        return;
    }
    if (const std::size_t dropped = written.dropped; dropped > 0)
        add_warning(warning_, file_ + ": " + std::to_string(dropped) + " line" + (dropped == 1 ? "" : "s") +
                                  " dropped to keep the file within " + std::to_string(bookmarks_write_limit >> 10) +
                                  " KiB (the oldest go first)");
}

std::string bookmarks_file_beside(const std::string& recent_file) {
    if (recent_file.empty()) return {};
    return (std::filesystem::path(recent_file).parent_path() / "camera-bookmarks").string();
}

}  // namespace caustica::ui
