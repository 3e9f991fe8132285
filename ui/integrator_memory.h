// The integrator the person picked for each scene in the preview, kept between runs in one small
// text file that every preview of the user shares (docs/PREVIEW.md, "What you see is what you
// save"): a scene opened again starts with the person's integrator instead of the script's.
#pragma once

#include "core/scene/options.h"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace caustica::ui {

/// The file holds one scene a line, "SCENE<TAB>INTEGRATOR" (the --integrator name; SCENE escaped by
/// escape_field), the scene picked last at the end. A lookup reads the file again, so a choice made
/// in another preview counts at the next open. A change takes the lock file beside it (FILE.lock),
/// re-reads the file, changes only its own scene's line and replaces the file atomically within
/// write_limit; if the lock is not had within the wait, nothing changes and warning() says so. A
/// line that cannot be read (an integrator this build does not know, a hand edit) is skipped with a
/// warning and written back as it was. A file over the read limit, or one that is not a regular
/// file, is ignored with a warning and never written over: changes then last until the preview
/// closes.
class IntegratorMemory {
public:
    /// The file is read up to this size: a larger one is ignored and never written over.
    static constexpr std::size_t read_limit = 1u << 20;
    /// The file is written up to this size, well under the read limit: the scenes picked last are
    /// kept, the others dropped (with a warning).
    static constexpr std::size_t write_limit = read_limit / 4;
    /// How long a change waits for another preview's change of the file to finish.
    static constexpr double lock_wait_seconds = 2.0;

    /// Reads `file` ("" = kept in memory only); a change waits at most `lock_wait` seconds for the
    /// lock.
    explicit IntegratorMemory(std::string file, double lock_wait = lock_wait_seconds);
    /// The integrator remembered for `scene` (an absolute path), if any.
    std::optional<IntegratorKind> of(const std::string& scene);
    /// Remembers `integrator` for `scene`, or forgets the scene when it is nullopt, and writes the
    /// file when that changes it.
    void set(const std::string& scene, std::optional<IntegratorKind> integrator);
    /// What went wrong reading or writing the file, or what the last write dropped ("" = nothing).
    const std::string& warning() const { return warning_; }

private:
    struct Entry {
        std::string scene;
        IntegratorKind integrator = IntegratorKind::classic;
        std::string raw;  ///< an unreadable line, kept verbatim ("" = a scene's integrator)
    };
    /// Reads the file into `entries`; false (and `entries` untouched) when it is not to be read or
    /// written over (warning_ says why).
    bool read(std::vector<Entry>& entries);
    /// Writes `entries_`, the newest lines that fit in write_limit (the others
    /// are dropped from `entries_` too, with a warning).
    void write();
    std::string file_, warning_;
    double lock_wait_seconds_;
    std::vector<Entry> entries_;
};

/// Where the integrators are kept: "scene-integrators" beside the recent list ("" when that is "").
std::string integrator_memory_beside(const std::string& recent_file);

}  // namespace caustica::ui
