// The fuzz targets (docs/RELIABILITY.md, "Fuzzing"). Each takes one input and returns 0 once the
// code under test has answered it as documented: a result, or its error (InputError, or the
// runtime_error of the PNG reader). Anything else ends the process and is a finding: a crash, a
// sanitizer report, an uncaught exception, a broken invariant of the result (fuzz_require).
// The same functions run under libFuzzer (libfuzzer_main.cpp, build-fuzz) and replay
// fuzz/regressions/<target>/ in the test suite (tests/repro/test_fuzz_regressions.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace caustica::fuzz {

/// Script text -> SceneScript or InputError, then the first render at 8 x 8 on one thread.
namespace scene_loader {
int fuzz_one(const std::uint8_t* data, std::size_t size);
}

/// OBJ text -> MeshData (every index in range, every coordinate finite) or InputError.
namespace obj_reader {
int fuzz_one(const std::uint8_t* data, std::size_t size);
}

/// PNG bytes -> Png8 (size consistent with the header and the limits) or std::runtime_error.
namespace png_reader {
int fuzz_one(const std::uint8_t* data, std::size_t size);
}

/// One target by name, for the replay test and the libFuzzer executables.
struct Target {
    const char* name;  ///< also the folder of its corpus and regressions
    int (*fuzz_one)(const std::uint8_t*, std::size_t);
};

inline constexpr Target targets[] = {
    {"scene_loader", scene_loader::fuzz_one},
    {"obj_reader", obj_reader::fuzz_one},
    {"png_reader", png_reader::fuzz_one},
};

/// Ends the process with `what` on stderr unless `condition` holds: a finding.
void fuzz_require(bool condition, const char* what);

}  // namespace caustica::fuzz
