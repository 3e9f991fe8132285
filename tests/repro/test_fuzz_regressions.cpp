// Replays fuzz/regressions/<target>/: every input that once crashed a fuzz target (or broke one
// of its invariants) runs through the same fuzz_one function, here without libFuzzer. A
// regression ends this test's process (crash, sanitizer report, abort), which fails it.
#include "fuzz/fuzz_targets.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

/// The inputs of one target's regression folder, sorted by name.
std::vector<fs::path> regression_inputs(const std::string& target) {
    const fs::path folder = fs::path(CAUSTICA_SOURCE_DIR) / "fuzz" / "regressions" / target;
    std::vector<fs::path> inputs;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder))
        if (entry.is_regular_file() && entry.path().filename().string().front() != '.') inputs.push_back(entry.path());
    std::sort(inputs.begin(), inputs.end());
    return inputs;
}

void replay(const caustica::fuzz::Target& target) {
    const std::vector<fs::path> inputs = regression_inputs(target.name);
    ASSERT_FALSE(inputs.empty()) << "no inputs in fuzz/regressions/" << target.name;
    for (const fs::path& input : inputs) {
        // Printed first: if the input brings the process down, the log says which one it was.
        std::fprintf(stderr, "replaying %s\n", input.c_str());
        std::ifstream in(input, std::ios::binary);
        const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        EXPECT_EQ(target.fuzz_one(bytes.data(), bytes.size()), 0) << input;
    }
}

const caustica::fuzz::Target& target_named(const std::string& name) {
    for (const caustica::fuzz::Target& target : caustica::fuzz::targets)
        if (name == target.name) return target;
    throw std::logic_error("no fuzz target " + name);
}

}  // namespace

TEST(FuzzRegressions, SceneLoader) { replay(target_named("scene_loader")); }
TEST(FuzzRegressions, ObjReader) { replay(target_named("obj_reader")); }
TEST(FuzzRegressions, PngReader) { replay(target_named("png_reader")); }
