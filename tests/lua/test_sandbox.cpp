// The scene sandbox as a hostile script would try it: no function object from the call stack,
// reads only of regular files under the scene folder (symlinks followed by the real file system),
// no writes outside the current folder, bounded time inside long library calls, one memory budget
// for everything the script makes the renderer hold, and the loader's process boundary.
#include "core/lua/scene_loader.h"
#include "core/lua/scene_wire.h"
#include "core/io/png_io.h"
#include "tests/scene_test_helpers.h"
#include "tests/temp_folder.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>

namespace caustica {
namespace {

namespace fs = std::filesystem;
using testing::TempFolder;
using Clock = std::chrono::steady_clock;

using testing::load_error;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

const char* scene_tail =
    "local l = gr.light({0, 5, 5}, {1, 1, 1}, {1, 0, 0})\n"
    "gr.render(root, 'out.png', 8, 8, {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 50, {0.1, 0.1, 0.1}, {l})\n";

TEST(Sandbox, GetinfoNeverHandsOutAFunction) {
    TempFolder dir;
    const std::string scene = dir.write("s.lua",
        "local got = 'unset'\n"
        "load(function() got = debug.getinfo(2, 'f').func; return nil end)\n"
        "assert(got == nil, 'getinfo gave ' .. tostring(got))\n"
        "assert(debug.getinfo(1).func == nil)\n"
        "assert(debug.getinfo(1, 'Sl').currentline == 5)\n"
        "assert(debug.getinfo(2) == nil)  -- run as the main script\n"
        "local root = gr.node('root')\n" + std::string(scene_tail));
    EXPECT_EQ(load_error(scene), "(no error)");
}

TEST(Sandbox, BinaryChunksNeverLoad) {
    TempFolder dir;
    // "\27Lua": a binary chunk's signature; every route to load must refuse it as text-only.
    const std::string scene = dir.write("s.lua",
        "local ok, err = load('\\27LuaT\\0', 'x', 'b')\n"
        "assert(ok == nil and err:find('binary', 1, true), err)\n"
        "local f, e = loadstring('\\27LuaT')\n"
        "assert(f == nil)\n"
        "error('done')\n");
    EXPECT_NE(load_error(scene).find("s.lua:5: done"), std::string::npos) << load_error(scene);
}

TEST(Sandbox, SharedMetatablesAreLocked) {
    TempFolder dir;
    const std::string io_scene = dir.write("io.lua", "local mt = getmetatable(io.stdout)\nmt.__gc = function() end\n");
    EXPECT_NE(load_error(io_scene).find("io.lua:2:"), std::string::npos) << load_error(io_scene);
    const std::string node_scene =
        dir.write("node.lua", "local mt = getmetatable(gr.node('a'))\nassert(mt == 'locked')\nerror('ok')\n");
    EXPECT_NE(load_error(node_scene).find("node.lua:3: ok"), std::string::npos) << load_error(node_scene);
    const std::string string_scene = dir.write("str.lua", "assert(getmetatable('') == 'locked')\nerror('ok')\n");
    EXPECT_NE(load_error(string_scene).find("str.lua:2: ok"), std::string::npos) << load_error(string_scene);
}

TEST(Sandbox, SymlinksOutOfTheFolderAreRefusedWhateverThePath) {
    TempFolder outside;
    outside.write("secret.txt", "SECRET-CONTENT\n");
    TempFolder dir;
    fs::create_symlink(outside.file("secret.txt"), dir.file("link.txt"));
    fs::create_directories(dir.file(std::string(250, 'a')));
    fs::create_symlink("loop", dir.file("loop"));  // a looping link before '..' must not defeat the check
    for (const std::string& name : {std::string("link.txt"), std::string(250, 'a') + "/../link.txt",
                                    std::string("loop/../link.txt"), outside.file("secret.txt")}) {
        const std::string scene = dir.write("s.lua", "local f, err = io.open('" + name +
                                                         "')\nif f then error(f:read('a')) end\nerror(err)\n");
        const std::string error = load_error(scene);
        EXPECT_EQ(error.find("SECRET"), std::string::npos) << name << ": " << error;
        EXPECT_NE(error.find("outside the scene folder"), std::string::npos) << name << ": " << error;
    }
    const std::string lines = dir.write("l.lua", "for line in io.lines('link.txt') do error(line) end\n");
    EXPECT_NE(load_error(lines).find("l.lua:1: io.lines: 'link.txt' is outside"), std::string::npos) << load_error(lines);
}

TEST(Sandbox, RequireFollowsTheSameRule) {
    TempFolder outside;
    outside.write("evil.lua", "error('EVIL RAN')\n");
    TempFolder dir;
    fs::create_symlink(outside.file("evil.lua"), dir.file("evil.lua"));
    fs::create_symlink(outside.path(), dir.file("include"));
    fs::create_symlink("/etc/passwd", dir.file("passwd.lua"));
    for (const char* module : {"evil", "passwd"}) {
        const std::string scene = dir.write("s.lua", std::string("require('") + module + "')\n");
        const std::string error = load_error(scene);
        EXPECT_NE(error.find("s.lua:1: require: '"), std::string::npos) << error;
        EXPECT_NE(error.find("outside the scene folder"), std::string::npos) << error;
        EXPECT_EQ(error.find("EVIL"), std::string::npos) << error;
        EXPECT_EQ(error.find("root"), std::string::npos) << error;  // nothing of /etc/passwd leaks
    }
}

TEST(Sandbox, OnlyRegularFilesAreRead) {
    TempFolder dir;
    ASSERT_EQ(::mkfifo((dir.file("fifo.obj")).c_str(), 0600), 0);
    fs::create_symlink("/dev/zero", dir.file("zero.obj"));
    for (const char* name : {"fifo.obj", "zero.obj"}) {
        const std::string scene = dir.write("s.lua", std::string("gr.mesh('m', '") + name + "')\n");
        const auto start = Clock::now();
        const std::string error = load_error(scene);
        EXPECT_LT(seconds_since(start), caustica::testing::time_bound(5.0));
        EXPECT_NE(error.find("s.lua:1: gr.mesh: '"), std::string::npos) << error;
        EXPECT_NE(error.find("only regular files can be read"), std::string::npos) << error;
    }
    const std::string folder = dir.write("f.lua", "gr.texture('.')\n");
    EXPECT_NE(load_error(folder).find("is a folder"), std::string::npos) << load_error(folder);
}

TEST(Sandbox, AllowReadWidensTheFolderForTheUserOnly) {
    TempFolder shared;
    Image image(2, 1);
    image.at(0, 0) = glm::vec3(1, 0, 0);
    image.at(1, 0) = glm::vec3(0, 1, 0);
    write_png_atomic(shared.file("tex.png"), image, PixelEncoding::clamped_linear);
    TempFolder dir;
    const std::string scene = dir.write("s.lua", "local t = gr.texture('" + (shared.file("tex.png")) +
                                                     "')\nlocal root = gr.node('root')\n" + scene_tail);
    EXPECT_NE(load_error(scene).find("s.lua:1: gr.texture: '"), std::string::npos);
    LoadSettings settings;
    settings.allow_read = {shared.path().string()};
    const SceneScript script = load_scene_script(scene, settings);
    ASSERT_EQ(script.renders.size(), 1u);
    ASSERT_EQ(script.renders[0].scene->textures.size(), 1u);
    const auto& decoded = script.renders[0].scene->textures[0].image;
    ASSERT_TRUE(decoded);
    EXPECT_EQ(decoded->width, 2);
    EXPECT_EQ(decoded->data[0], 255);

    const std::string widening = dir.write("w.lua", "gr.option('--allow-read /')\n");
    EXPECT_NE(load_error(widening).find("w.lua:1: gr.option: --allow-read is for the command line only"),
              std::string::npos)
        << load_error(widening);
}

TEST(Sandbox, TheSameFileUnderTwoNamesIsDecodedOnce) {
    TempFolder dir;
    Image image(4, 4);
    write_png_atomic(dir.file("a.png"), image, PixelEncoding::clamped_linear);
    fs::create_symlink("a.png", dir.file("b.png"));
    const std::string scene = dir.write("s.lua", "local a = gr.texture('a.png')\nlocal b = gr.texture('b.png')\n"
                                                 "local root = gr.node('root')\n" + std::string(scene_tail));
    const SceneScript script = load_scene_script(scene);
    const SceneDesc& desc = *script.renders.at(0).scene;
    ASSERT_EQ(desc.textures.size(), 2u);
    EXPECT_EQ(desc.textures[0].image.get(), desc.textures[1].image.get());
}

TEST(Sandbox, OutputNamesStayBelowTheCurrentFolder) {
    TempFolder dir;
    for (const char* name : {"/tmp/victim.png", "../victim.png", "a/../../victim.png"}) {
        const std::string scene = dir.write("s.lua", "local root = gr.node('root')\nlocal l = gr.light({0,5,5},{1,1,1},{1,0,0})\n"
                                                     "gr.render(root, '" + std::string(name) +
                                                     "', 8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 50, {0,0,0}, {l})\n");
        const std::string error = load_error(scene);
        EXPECT_NE(error.find("s.lua:3: gr.render: output file name '" + std::string(name) + "' must"), std::string::npos)
            << error;
        LoadSettings given;
        given.output_given = true;  // -o is the user's: the script's name is not used
        EXPECT_EQ(load_error(scene, given), "(no error)");
    }
    const std::string fine = dir.write("ok.lua", "local root = gr.node('root')\n" + std::string(scene_tail));
    EXPECT_EQ(load_error(fine), "(no error)");
}

TEST(Sandbox, LongLibraryCallsStopAtTheTimeLimit) {
    TempFolder dir;
    const std::pair<const char*, const char*> cases[] = {
        {"pattern.lua", "local s = string.rep('a', 3000)\nlocal r = string.find(s, string.rep('.-', 12) .. 'b')\n"},
        {"move.lua", "local x = 1\ntable.move({}, 1, 1e15, 2)\n"},
        {"sort.lua", "local t = {}\nfor i = 1, 3e6 do t[i] = (i * 7919) % 1000003 end\nfor k = 1, 100 do table.sort(t) end\n"},
    };
    LoadSettings settings;
    settings.timeout_seconds = 1.0;
    for (const auto& [name, text] : cases) {
        const std::string scene = dir.write(name, text);
        const auto start = Clock::now();
        const std::string error = load_error(scene, settings);
        const double elapsed = seconds_since(start);
        EXPECT_LT(elapsed, caustica::testing::time_bound(1.0 + 1.5)) << name;  // the limit, the stop request and the grace period
        EXPECT_NE(error.find("script stopped after 1 s (--script-timeout)"), std::string::npos) << error;
        EXPECT_NE(error.find(std::string(name) + ":"), std::string::npos) << error;
    }
}

TEST(Sandbox, CancelStopsARunawayPatternAtOnce) {
    TempFolder dir;
    const std::string scene =
        dir.write("s.lua", "local s = string.rep('a', 5000)\nlocal r = string.find(s, string.rep('.-', 14) .. 'b')\n");
    std::atomic<bool> cancel{false};
    LoadSettings settings;
    settings.cancel = &cancel;
    std::thread canceller([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        cancel = true;
    });
    const auto start = Clock::now();
    EXPECT_THROW(load_scene_script(scene, settings), ScriptCancelled);
    canceller.join();
    EXPECT_LT(seconds_since(start), caustica::testing::time_bound(0.3 + 0.5));
}

TEST(Sandbox, OneBudgetForEverythingTheScriptMakesTheRendererHold) {
    TempFolder dir;
    const std::pair<const char*, const char*> cases[] = {
        {"names.lua", "local s = string.rep('n', 1e7)\nfor i = 1, 100 do gr.node(s) end\n"},
        {"snapshots.lua", "local root = gr.node('root')\nfor i = 1, 20000 do root:add_child(gr.sphere('s')) end\n"
                          "local l = gr.light({5,5,5},{1,1,1},{1,0,0})\nfor i = 1, 2000 do\n"
                          "  gr.render(root, 'x.png', 8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 50, {0,0,0}, {l})\nend\n"},
        {"transforms.lua", "local n = gr.node('n')\nfor i = 1, 1e9 do n:translate(1, 0, 0) end\n"},
        {"rep.lua", "local s = string.rep('x', 1e9)\n"},
    };
    const int expected_line[] = {2, 5, 2, 1};
    LoadSettings settings;
    settings.memory_limit_bytes = std::size_t(256) << 20;
    for (std::size_t i = 0; i < std::size(cases); ++i) {
        const std::string scene = dir.write(cases[i].first, cases[i].second);
        const auto start = Clock::now();
        const std::string error = load_error(scene, settings);
        EXPECT_LT(seconds_since(start), caustica::testing::time_bound(20.0)) << cases[i].first;
        EXPECT_NE(error.find(std::string(cases[i].first) + ":" + std::to_string(expected_line[i]) + ":"),
                  std::string::npos)
            << error;
        EXPECT_NE(error.find("256 MiB"), std::string::npos) << error;
    }
}

TEST(Sandbox, TheMemoryBudgetCannotBeCaught) {
    // A pcall around the allocation that goes over the budget must not let the script carry on
    // (here: into a loop the time limit alone would end), whether the Lua heap or the scene data
    // (names, warnings) went over it. The error names the line that went over.
    TempFolder dir;
    const std::pair<const char*, const char*> cases[] = {
        {"heap.lua", "local t = {}\nlocal ok = pcall(function() t[1] = string.rep('x', 1e9) end)\n"
                     "while true do t[2] = ok end\n"},
        {"names.lua", "local s = string.rep('n', 1e7)\nlocal ok = pcall(function() for i = 1, 100 do gr.node(s) end end)\n"
                      "while true do s = ok end\n"},
        {"nested.lua", "local ok = pcall(pcall, function() local s = string.rep('y', 1e9) end)\n"
                       "local n = 0\nwhile true do n = n + 1 end\n"},
    };
    LoadSettings settings;
    settings.memory_limit_bytes = std::size_t(256) << 20;
    settings.timeout_seconds = 60.0;
    for (const auto& [name, text] : cases) {
        const std::string scene = dir.write(name, text);
        const auto start = Clock::now();
        const std::string error = load_error(scene, settings);
        EXPECT_LT(seconds_since(start), caustica::testing::time_bound(10.0)) << name;
        const std::string line = std::string(name) + (std::string(name) == "nested.lua" ? ":1:" : ":2:");
        EXPECT_NE(error.find(line), std::string::npos) << error;
        EXPECT_NE(error.find("256 MiB"), std::string::npos) << error;
        EXPECT_EQ(error.find("stopped after"), std::string::npos) << error;
    }
}

TEST(SceneWire, RoundTripKeepsEverythingAndSharing) {
    TempFolder dir;
    Image image(3, 2);
    write_png_atomic(dir.file("t.png"), image, PixelEncoding::clamped_linear);
    dir.write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string scene = dir.write("s.lua",
        "local m = gr.material({0.1,0.2,0.3},{0.4,0.5,0.6},25)\nm:set_ri(1.5)\nm:set_texture(gr.texture('t.png'))\n"
        "local root = gr.node('root')\nlocal s = gr.sphere('ball')\ns:set_material(m)\ns:translate(1,2,3)\ns:rotate('y', 30)\n"
        "root:add_child(s)\nroot:add_child(gr.mesh('tri', 'm.obj'))\nroot:add_child(gr.difference('d', gr.cube('a'), gr.sphere('b')))\n"
        "warn('hello')\ngr.option('--aa-grid 5')\n" + std::string(scene_tail) +
        "gr.render(root, 'two.png', 16, 8, {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 40, {0.2, 0.1, 0.1}, {l})\n");
    const SceneScript original = load_scene_script_in_process(scene);
    const SceneScript copy = scene_lua::decode_scene_script(scene_lua::encode_scene_script(original));
    ASSERT_EQ(copy.renders.size(), 2u);
    EXPECT_EQ(copy.warnings, original.warnings);
    EXPECT_EQ(copy.path, original.path);
    for (std::size_t r = 0; r < 2; ++r) {
        const RenderJob& a = original.renders[r];
        const RenderJob& b = copy.renders[r];
        EXPECT_EQ(a.output, b.output);
        EXPECT_EQ(a.width, b.width);
        EXPECT_EQ(a.camera.fovy_degrees, b.camera.fovy_degrees);
        EXPECT_EQ(a.options.aa_grid, b.options.aa_grid);
        EXPECT_EQ(a.where.str(), b.where.str());
        ASSERT_EQ(a.scene->nodes.size(), b.scene->nodes.size());
        for (std::size_t n = 0; n < a.scene->nodes.size(); ++n) {
            EXPECT_EQ(a.scene->nodes[n].name, b.scene->nodes[n].name);
            EXPECT_EQ(a.scene->nodes[n].children, b.scene->nodes[n].children);
            EXPECT_EQ(a.scene->nodes[n].transforms.size(), b.scene->nodes[n].transforms.size());
            EXPECT_EQ(a.scene->nodes[n].where.str(), b.scene->nodes[n].where.str());
        }
        EXPECT_EQ(b.scene->materials.at(0).refractive_index, 1.5);
        EXPECT_EQ(b.scene->meshes.at(0)->triangles.size(), 1u);
        EXPECT_EQ(b.scene->textures.at(0).image->width, 3);
    }
    // Meshes and images are shared between snapshots, and written once.
    EXPECT_EQ(copy.renders[0].scene->meshes[0].get(), copy.renders[1].scene->meshes[0].get());
    EXPECT_EQ(copy.renders[0].scene->textures[0].image.get(), copy.renders[1].scene->textures[0].image.get());
    // Every truncation of the bytes is refused cleanly.
    const std::string bytes = scene_lua::encode_scene_script(original);
    for (std::size_t cut = 0; cut < bytes.size(); cut += 1 + bytes.size() / 500)
        EXPECT_THROW(scene_lua::decode_scene_script(std::string_view(bytes).substr(0, cut)), std::runtime_error);
}

TEST(SceneProcess, ScriptOutputIsNotDuplicatedAndNothingLeaks) {
    TempFolder dir;
    const std::string scene = dir.write("s.lua", "io.write('from the script\\n')\nlocal root = gr.node('root')\n" +
                                                     std::string(scene_tail));
    ::testing::internal::CaptureStdout();
    const SceneScript script = load_scene_script(scene);
    const std::string out = ::testing::internal::GetCapturedStdout();
    EXPECT_EQ(out, "from the script\n");
    EXPECT_EQ(script.renders.size(), 1u);
}

}  // namespace
}  // namespace caustica
