// A script's text on its way to the user (docs/RELIABILITY.md, "Script text reaches the user
// bounded and visible"): errors, warnings and print output arrive bounded, with what was left out
// counted, and with terminal escape sequences made visible; UTF-8 passes unchanged. A loader
// process that sends a huge message cannot make the caller hold it.
#include "core/lua/scene_loader.h"
#include "core/util/printable_text.h"
#include "tests/scene_test_helpers.h"
#include "tests/temp_folder.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace caustica {
namespace {

using testing::TempFolder;
using testing::load_error;
using Clock = std::chrono::steady_clock;

/// What a scene needs after its body to load: a root and one gr.render.
const char* scene_tail =
    "local root = gr.node('root')\n"
    "local l = gr.light({0, 5, 5}, {1, 1, 1}, {1, 0, 0})\n"
    "gr.render(root, 'out.png', 8, 8, {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 50, {0.1, 0.1, 0.1}, {l})\n";

/// The escape sequences of the audit: clear the screen, set the window title, write the clipboard.
const char* escapes_lua = "'\\27[2J\\27]0;title\\7\\27]52;c;ZXZpbA==\\7'";
const char* escapes_shown = "\\x1b[2J\\x1b]0;title\\x07\\x1b]52;c;ZXZpbA==\\x07";

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

std::size_t occurrences(const std::string& text, const std::string& part) {
    std::size_t count = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + part.size())) ++count;
    return count;
}

/// True when `text` has no byte a terminal acts on (C0 controls but newline and tab, DEL, ESC).
bool has_no_control_bytes(const std::string& text) {
    return std::none_of(text.begin(), text.end(), [](char c) {
        const auto b = static_cast<unsigned char>(c);
        return (b < 0x20 && b != '\n' && b != '\t') || b == 0x7f;
    });
}

/// Runs `scene` as load_scene_script does; what the script printed to standard output.
std::string printed_by(const std::string& scene, SceneScript& script) {
    ::testing::internal::CaptureStdout();
    try {
        script = load_scene_script(scene);
    } catch (...) {
        ::testing::internal::GetCapturedStdout();
        throw;
    }
    return ::testing::internal::GetCapturedStdout();
}

TEST(ScriptText, AHugeErrorArrivesBoundedQuicklyAndSaysHowMuchWasLeftOut) {
    TempFolder dir;
    const std::string located = dir.write("s.lua", "error(string.rep('E', 5e7))\n");
    const std::string unlocated = dir.write("t.lua", "error(string.rep('E', 5e7), 0)\n");
    for (const std::string& scene : {located, unlocated}) {
        const auto start = Clock::now();
        const std::string error = load_error(scene);
        const double seconds = seconds_since(start);
        EXPECT_LT(seconds, testing::time_bound(3.0)) << scene;
        const std::string where = scene + ":1: ";
        ASSERT_EQ(error.rfind(where, 0), 0u) << error.substr(0, 200);
        EXPECT_LE(error.size(), where.size() + printable_text_max_bytes(script_text_limit));
        const std::size_t kept = static_cast<std::size_t>(std::count(error.begin() + where.size(), error.end(), 'E'));
        EXPECT_GT(kept, script_text_limit / 2);
        EXPECT_EQ(error.substr(where.size()),
                  std::string(kept, 'E') + " … and " + std::to_string(50'000'000 - kept) + " more bytes");
    }
}

TEST(ScriptText, EscapeSequencesInErrorsWarningsAndPrintAreMadeVisible) {
    TempFolder dir;
    const std::string failing = dir.write("e.lua", std::string("error(") + escapes_lua + ")\n");
    const std::string error = load_error(failing);
    EXPECT_EQ(error, failing + ":1: " + escapes_shown);

    const std::string printing = dir.write("p.lua", std::string("print(") + escapes_lua + ", 'x')\nio.write(" + escapes_lua +
                                                        ", 1, 2.5, '\\n')\nio.stderr:write('')\nwarn(" + escapes_lua +
                                                        ")\n" + scene_tail);
    SceneScript script;
    const std::string out = printed_by(printing, script);
    EXPECT_EQ(out, std::string(escapes_shown) + "\tx\n" + escapes_shown + "12.5\n");
    ASSERT_EQ(script.warnings.size(), 1u);
    EXPECT_EQ(script.warnings[0], printing + ":4: " + escapes_shown);
}

TEST(ScriptText, Utf8TextPassesUnchanged) {
    TempFolder dir;
    const std::string scene =
        dir.write("café.lua", "print('café', 'naïve')\nwarn('gr.node café')\n" + std::string(scene_tail));
    SceneScript script;
    EXPECT_EQ(printed_by(scene, script), "café\tnaïve\n");
    EXPECT_EQ(script.warnings, std::vector<std::string>{scene + ":2: gr.node café"});
    const std::string failing = dir.write("échec.lua", "local name = 'café'\nerror('node ' .. name .. ' is missing')\n");
    EXPECT_EQ(load_error(failing), failing + ":2: node café is missing");
}

TEST(ScriptText, AFloodOfPrintIsBoundedAndOneLineSaysHowMuchWasLeftOut) {
    TempFolder dir;
    const std::string scene =
        dir.write("s.lua", "for i = 1, 20000 do print(string.rep('p', 100)) end\n" + std::string(scene_tail));
    SceneScript script;
    const auto start = Clock::now();
    const std::string out = printed_by(scene, script);
    const double seconds = seconds_since(start);
    EXPECT_LT(seconds, testing::time_bound(3.0));
    EXPECT_LE(out.size(), script_output_limit);
    EXPECT_EQ(out.size() % 101, 0u);  // whole lines only
    EXPECT_TRUE(has_no_control_bytes(out));
    const std::size_t lines = occurrences(out, "\n");
    ASSERT_FALSE(script.warnings.empty());
    EXPECT_EQ(script.warnings.back(), scene + ": … and " + std::to_string((20000 - lines) * 100) +
                                          " more bytes of script output (print, io.write, warn) left out"
                                          " (at most 64 KiB are shown)");
}

TEST(ScriptText, AFloodOfWarningsIsBoundedAndNotHeld) {
    TempFolder dir;
    const std::pair<const char*, const char*> cases[] = {
        {"big.lua", "local s = string.rep('w', 1e7)\nfor i = 1, 100 do warn(s) end\n"},
        {"many.lua", "for i = 1, 1e5 do warn('w') end\n"},
        {"pieces.lua", "local s = string.rep('w', 1e6)\nfor i = 1, 20 do warn(s, s, s, s) end\n"},
    };
    for (const auto& [name, body] : cases) {
        const std::string scene = dir.write(name, body + std::string(scene_tail));
        const auto start = Clock::now();
        const SceneScript script = load_scene_script(scene);
        const double seconds = seconds_since(start);
        EXPECT_LT(seconds, testing::time_bound(3.0)) << name;
        std::size_t bytes = 0;
        for (const std::string& warning : script.warnings) {
            bytes += warning.size() + 1;
            EXPECT_LE(warning.size(), printable_text_max_bytes(script_text_limit)) << name;
        }
        EXPECT_LE(bytes, script_output_limit + printable_text_max_bytes(shown_message_limit)) << name;
        ASSERT_FALSE(script.warnings.empty());
        EXPECT_NE(script.warnings.back().find(" more bytes of script output"), std::string::npos) << name;
    }
}

/// Sets an environment variable for the scope of a test.
class ScopedEnvironment {
public:
    ScopedEnvironment(const char* name, const std::string& value) : name_(name) { ::setenv(name, value.c_str(), 1); }
    ~ScopedEnvironment() { ::unsetenv(name_); }
    ScopedEnvironment(const ScopedEnvironment&) = delete;
    ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

private:
    const char* name_;
};

TEST(ScriptText, ALoaderSendingAHugeMessageCannotMakeTheCallerHoldIt) {
    // A stand-in for the loader process (CAUSTICA_SCENE_LOADER) whose reply is a well-formed 'E'
    // message of 5e7 ESC bytes, as a broken or hostile loader could send.
    TempFolder dir;
    const std::uint64_t length = 1 + 50'000'000;
    std::string header;
    for (int i = 0; i < 8; ++i) {
        char octal[8];
        std::snprintf(octal, sizeof octal, "\\%03o", static_cast<unsigned>((length >> (8 * i)) & 0xff));
        header += octal;
    }
    const std::string loader = dir.write("loader.sh", "#!/bin/sh\nprintf '" + header + "E' >&4\n"
                                                      "head -c 50000000 /dev/zero | tr '\\000' '\\033' >&4\n");
    ASSERT_EQ(::chmod(loader.c_str(), 0755), 0);
    const ScopedEnvironment stand_in("CAUSTICA_SCENE_LOADER", loader);
    const auto start = Clock::now();
    const std::string error = load_error(dir.write("s.lua", scene_tail));
    const double seconds = seconds_since(start);
    EXPECT_LT(seconds, testing::time_bound(5.0));
    EXPECT_LE(error.size(), printable_text_max_bytes(printable_text_max_bytes(shown_message_limit)));
    EXPECT_TRUE(has_no_control_bytes(error));
    const std::size_t kept = occurrences(error, "\\x1b");
    EXPECT_GT(kept, shown_message_limit / 8);
    EXPECT_EQ(error, [&] {
        std::string shown;
        for (std::size_t i = 0; i < kept; ++i) shown += "\\x1b";
        return shown + " … and " + std::to_string(50'000'000 - kept) + " more bytes";
    }());
}

}  // namespace
}  // namespace caustica
