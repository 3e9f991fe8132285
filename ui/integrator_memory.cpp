#include "ui/integrator_memory.h"

#include "core/integrators/registry.h"
#include "ui/small_file.h"

#include <algorithm>
#include <filesystem>
#include <string_view>

namespace caustica::ui {

IntegratorMemory::IntegratorMemory(std::string file, double lock_wait)
    : file_(std::move(file)), lock_wait_seconds_(lock_wait) {
    if (!file_.empty()) read(entries_);
}

bool IntegratorMemory::read(std::vector<Entry>& entries) {
    warning_.clear();
    const SmallFile file = read_small_file(file_, read_limit);
    if (!file.problem.empty()) {
        warning_ = file_ + ": " + file.problem +
                   "; the integrators picked per scene are not read from it, and it is never written over";
        return false;
    }
    entries.clear();
    const std::string_view text = file.text;
    int line_number = 0, bad = 0, first_bad = 0;
    for (std::size_t start = 0; start < text.size();) {
        const std::size_t stop = std::min(text.find('\n', start), text.size());
        const std::string_view line = text.substr(start, stop - start);
        start = stop + 1;
        ++line_number;
        if (line.empty()) continue;
        const std::size_t tab = line.find('\t');
        const IntegratorEntry* integrator =
            tab == std::string_view::npos || tab == 0 ? nullptr : find_integrator(line.substr(tab + 1));
        if (!integrator) {  // kept verbatim and written back: a hand edit is the person's to repair
            if (bad++ == 0) first_bad = line_number;
            entries.push_back({{}, IntegratorKind::classic, std::string(line)});
            continue;
        }
        entries.push_back({unescape_field(std::string(line.substr(0, tab))), integrator->kind, {}});
    }
    if (bad > 0)
        warning_ = file_ + ": " + std::to_string(bad) + " unreadable line" + (bad == 1 ? "" : "s") +
                   " ignored (kept in the file; first: line " + std::to_string(first_bad) + ")";
    return true;
}

std::optional<IntegratorKind> IntegratorMemory::of(const std::string& scene) {
    if (!file_.empty()) read(entries_);  // a file it refuses leaves this session's choices
    for (const Entry& e : entries_)
        if (e.raw.empty() && e.scene == scene) return e.integrator;
    return std::nullopt;
}

void IntegratorMemory::set(const std::string& scene, std::optional<IntegratorKind> integrator) {
    // The scene's line goes to the end (the newest, kept longest); false when nothing changes.
    auto apply = [&](std::vector<Entry>& entries) {
        auto same = [&](const Entry& e) { return e.raw.empty() && e.scene == scene; };
        const auto found = std::find_if(entries.begin(), entries.end(), same);
        const std::optional<IntegratorKind> had =
            found == entries.end() ? std::nullopt : std::optional<IntegratorKind>(found->integrator);
        if (had == integrator) return false;
        std::erase_if(entries, same);
        if (integrator) entries.push_back({scene, *integrator, {}});
        return true;
    };
    if (file_.empty()) {
        apply(entries_);
        return;
    }
    // Another preview may change the file at the same time: under the lock, start from what is
    // there now and change only this scene's line.
    const FileLock lock(file_ + ".lock", lock_wait_seconds_);
    if (!lock.held()) {
        warning_ = file_ + ".lock: " + lock.problem() + "; the integrator picked for this scene is not remembered (pick it again)";
        return;
    }
    std::vector<Entry> current;
    if (!read(current)) {
        apply(entries_);
        warning_ += "; this choice lasts until the preview closes";
        return;
    }
    const bool changed = apply(current);
    entries_ = std::move(current);
    if (changed) write();
}

void IntegratorMemory::write() {
    std::vector<std::string> lines;
    lines.reserve(entries_.size());
    for (const Entry& e : entries_)
        lines.push_back(e.raw.empty() ? escape_field(e.scene) + '\t' + integrator_entry(e.integrator).name : e.raw);
    const LinesWritten written = write_newest_lines(file_, lines, write_limit);
    keep_flagged(entries_, written.kept);
    if (!written.problem.empty()) {
        warning_ = file_ + ": cannot write the integrators picked per scene (" + written.problem + ")";
        return;
    }
    if (written.dropped == 0) return;
    if (!warning_.empty()) warning_ += "; ";
    warning_ += file_ + ": " + std::to_string(written.dropped) + (written.dropped == 1 ? " line" : " lines") +
                " dropped to keep the file within " + std::to_string(write_limit >> 10) +
                " KiB (the scenes picked longest ago go first)";
}

std::string integrator_memory_beside(const std::string& recent_file) {
    if (recent_file.empty()) return {};
    return (std::filesystem::path(recent_file).parent_path() / "scene-integrators").string();
}

}  // namespace caustica::ui
