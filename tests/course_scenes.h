// The course scenes of ../shared/cs488 (beside the repository): tests that need them skip, with a
// message saying what is missing, when they are absent, so that a clone on its own passes.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace caustica::testing {

/// The course scene folder: $CAUSTICA_CS488_DIR when set (to test elsewhere, or the skip itself),
/// else the ../shared/cs488 found at configure time.
inline std::string cs488_dir() {
    const char* from_environment = std::getenv("CAUSTICA_CS488_DIR");
    return from_environment && *from_environment ? from_environment : CAUSTICA_CS488_DIR;
}

/// `cs488_dir()/name`.
inline std::string cs488_file(const std::string& name) { return cs488_dir() + "/" + name; }

/// Whether the course scene folder is there (checked at run time).
inline bool have_cs488() { return std::filesystem::is_directory(cs488_dir()); }

}  // namespace caustica::testing

/// Ends the test as skipped unless the course scenes are there.
#define CAUSTICA_SKIP_WITHOUT_CS488()                                                                         \
    do {                                                                                                      \
        if (!::caustica::testing::have_cs488())                                                               \
            GTEST_SKIP() << "../shared/cs488 not found: " << ::caustica::testing::cs488_dir()                 \
                         << " is missing; the course scenes (the shared folder beside the repository, or "    \
                            "$CAUSTICA_CS488_DIR) are needed for this test";                                  \
    } while (false)
