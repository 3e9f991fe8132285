// The Lua 5.1 names the original scenes were written against (docs/SCENE_LANGUAGE.md): string.gfind,
// table.getn, unpack, math.mod, math.pow, loadstring (text only, sandboxed), 5.1's math.random on
// glibc's rand(); and the course's gr.* calls that came with it: the inline gr.mesh,
// gr.isodecahedron, node:render and gr.joint.
#include "core/lua/scene_loader.h"
#include "core/lua/lua_random51.h"
#include "core/geometry/mesh_obj.h"
#include "tests/scene_test_helpers.h"
#include "tests/temp_folder.h"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace caustica {
namespace {

using scene_lua::GlibcRandom;
using testing::TempFolder;

using testing::load_error;

/// Runs `body` as s.lua (in the loader process) and returns what it passed to warn(), one entry a
/// call, without the "file:line: " prefix.
std::vector<std::string> warnings_of(const std::string& body, const LoadSettings& settings = {}) {
    TempFolder dir;
    const std::string path = dir.write("s.lua", body);
    const SceneScript script = load_scene_script(path, settings);
    std::vector<std::string> out;
    for (const std::string& warning : script.warnings) {
        const std::size_t colon = warning.find(": ", path.size());
        out.push_back(colon == std::string::npos ? warning : warning.substr(colon + 2));
    }
    return out;
}

/// Lua 5.1's r for one rand() value.
double fraction_51(std::int32_t rand_value) {
    return static_cast<double>(rand_value % 2147483647) / 2147483647.0;
}

std::string format7(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.7f", value);
    return text;
}

const char* render_line = "gr.render(root, 'out.png', 8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0,0,0}, {})\n";

// ---- library names ----

TEST(LuaCompat, GfindIteratesMatches) {
    EXPECT_EQ(warnings_of("for w in string.gfind('one two  three', '%a+') do warn(w) end\n"
                          "for d in string.gfind('1a2', '%d', 2) do warn(d) end  -- 5.1 had no init\n"
                          "for k, v in ('a=1, b=2'):gfind('(%w+)=(%w+)') do warn(k .. v) end\n"),
              (std::vector<std::string>{"one", "two", "three", "1", "2", "a1", "b2"}));
}

TEST(LuaCompat, TableGetnIsTheRawLength) {
    EXPECT_EQ(warnings_of("warn(tostring(table.getn({1, 2, 3})))\n"
                          "warn(tostring(table.getn({})))\n"
                          "warn(tostring(table.getn(setmetatable({1}, {__len = function() return 9 end}))))\n"),
              (std::vector<std::string>{"3", "0", "1"}));
}

TEST(LuaCompat, UnpackIsGlobal) {
    EXPECT_EQ(warnings_of("warn(tostring(select('#', unpack({1, 2, 3}))))\n"
                          "local a, b = unpack({4, 5, 6}, 2)\nwarn(a .. ',' .. b)\n"),
              (std::vector<std::string>{"3", "5,6"}));
}

TEST(LuaCompat, MathModIsFmod) {
    // fmod keeps the sign of the dividend, unlike % (which would give 2, -2, 0.5).
    EXPECT_EQ(warnings_of("warn(tostring(math.mod(-7, 3)))\nwarn(tostring(math.mod(7, -3)))\n"
                          "warn(tostring(math.mod(-7.5, 2)))\nwarn(tostring(math.mod(5.5, 2)))\n"
                          "warn(tostring(math.mod(7, 3)))\nlocal n = math.mod(1, 0)\nwarn(tostring(n ~= n))\n"),
              (std::vector<std::string>{"-1", "1", "-1.5", "1.5", "1", "true"}));
}

TEST(LuaCompat, MathPow) {
    EXPECT_EQ(warnings_of("warn(string.format('%g %g %g', math.pow(2, 10), math.pow(4, 0.5), math.pow(2, -1)))\n"),
              (std::vector<std::string>{"1024 2 0.5"}));
    // 5.1 printed whole numbers without ".0": names built from pow keep their 5.1 spelling.
    EXPECT_EQ(warnings_of("warn('tex' .. math.pow(2, 3) .. '.png', ' ', tostring(math.pow(2, 0.5) > 1.41), ' ', "
                          "tostring(math.pow(2, -1)))\n"),
              (std::vector<std::string>{"tex8.png true 0.5"}));
}

TEST(LuaCompat, LoadstringRunsTextInTheGlobals) {
    EXPECT_EQ(warnings_of("warn(tostring(loadstring('return 1 + 2')()))\n"
                          "loadstring('x = 5')()\nwarn(tostring(x))\n"
                          "local f, e = loadstring('return +')\nwarn(tostring(f == nil and e ~= nil))\n"
                          "local ok, m = pcall(loadstring('error(\"boom\")', '=chunk'))\nwarn(m)\n"
                          "warn(tostring(pcall(loadstring, function() return 'x' end)))\n"),
              (std::vector<std::string>{"3", "5", "true", "chunk:1: boom", "false"}));
}

TEST(LuaCompat, LoadstringRefusesBinaryAndStaysSandboxed) {
    TempFolder outside;
    const std::string secret = outside.write("secret.txt", "secret\n");
    TempFolder dir;
    dir.write("data.txt", "inside\n");
    const std::string scene = dir.write("s.lua",
        "local f, e = loadstring('\\27LuaT\\0\\25\\147')\n"
        "assert(f == nil and e:find('binary', 1, true), tostring(e))\n"
        "assert(loadstring('return io.open(...)')('" + secret + "') == nil)\n"
        "assert(loadstring('return io.open(...)')('data.txt'):read('l') == 'inside')\n"
        "local a, b, c, d, e = loadstring('return string.dump, dofile, loadfile, os.execute, debug.sethook')()\n"
        "assert(a == nil and b == nil and c == nil and d == nil and e == nil)\n"
        "assert(loadstring('return load')()('\\27LuaT\\0', 'x', 'b') == nil)\n"
        "error('done')\n");
    EXPECT_NE(load_error(scene).find("s.lua:8: done"), std::string::npos) << load_error(scene);

    // The loaded code runs under the script's time and memory limits.
    LoadSettings settings;
    settings.timeout_seconds = 1.0;
    settings.memory_limit_bytes = std::size_t(64) << 20;
    const std::string spin = dir.write("spin.lua", "local f = loadstring('while true do end')\nf()\n");
    EXPECT_NE(load_error(spin, settings).find("script stopped after 1 s"), std::string::npos) << load_error(spin, settings);
    const std::string grow = dir.write("grow.lua", "loadstring('local t = {} for i = 1, 1e9 do t[i] = i end')()\n");
    EXPECT_NE(load_error(grow, settings).find("memory limit of 64 MiB"), std::string::npos) << load_error(grow, settings);
}

TEST(LuaCompat, ModuleAndSeeallArePresent) {
    TempFolder dir;
    dir.write("lib.lua", "module(..., package.seeall)\nfunction twice(x) return math.floor(2 * x) end\n");
    const std::string path = dir.write("s.lua", "module(..., package.seeall)\nrequire 'lib'\n"
                                                "warn(tostring(lib.twice(21)) .. ' ' .. _NAME)\n");
    const SceneScript script = load_scene_script(path);
    ASSERT_EQ(script.warnings.size(), 1u);
    EXPECT_EQ(script.warnings[0], path + ":3: 42 s");
}

// ---- math.random as Lua 5.1 on glibc ----

TEST(LuaCompat, GeneratorIsGlibcRand) {
    GlibcRandom one;  // seeded with 1, as a program that never calls srand
    const std::int32_t from_one[] = {1804289383, 846930886, 1681692777, 1714636915, 1957747793, 424238335};
    for (std::int32_t expected : from_one) EXPECT_EQ(one.next(), expected);
    // glibc's answers for srand(42), srand(0) (= srand(1)) and srand(-5) (seed 4294967291).
    GlibcRandom g42(42), g0(0), g_minus5(static_cast<std::uint32_t>(-5));
    for (std::int32_t expected : {71876166, 708592740, 1483128881, 907283241, 442951012, 537146758})
        EXPECT_EQ(g42.next(), expected);
    for (std::int32_t expected : from_one) EXPECT_EQ(g0.next(), expected);
    for (std::int32_t expected : {1469203335, 1952330421, 2063378439, 796694348, 1716641992, 1857372861})
        EXPECT_EQ(g_minus5.next(), expected);
#ifdef __GLIBC__
    // Once against the C library itself (the generator never calls it).
    for (unsigned seed : {1u, 42u, 0u, 12345u, 4294967291u, 2147483648u}) {
        GlibcRandom ours(seed);
        std::srand(seed);
        for (int i = 0; i < 1000; ++i) ASSERT_EQ(ours.next(), std::rand()) << "seed " << seed << " draw " << i;
    }
#endif
}

TEST(LuaCompat, RandomFromSeedOneIsLua51s) {
    EXPECT_EQ(warnings_of("for i = 1, 6 do warn(string.format('%.7f', math.random())) end\n"),
              (std::vector<std::string>{"0.8401877", "0.3943829", "0.7830992", "0.7984400", "0.9116474", "0.1975514"}));
}

TEST(LuaCompat, EveryScriptStartsFromSeedOne) {
    // One generator per Lua state: a second script in the same process starts over.
    TempFolder dir;
    const std::string path = dir.write("s.lua", "warn(string.format('%.7f', math.random()))\n");
    for (int run = 0; run < 2; ++run)
        EXPECT_EQ(load_scene_script_in_process(path).warnings.at(0), path + ":1: 0.8401877");
}

TEST(LuaCompat, RandomseedCallsSrand) {
    GlibcRandom expected(42);
    std::vector<std::string> values;
    for (int i = 0; i < 6; ++i) values.push_back(format7(fraction_51(expected.next())));
    EXPECT_EQ(values, (std::vector<std::string>{"0.0334699", "0.3299642", "0.6906357", "0.4224867", "0.2062651",
                                                "0.2501285"}));
    EXPECT_EQ(warnings_of("math.random(); math.random()\nmath.randomseed(42)\n"
                          "for i = 1, 6 do warn(string.format('%.7f', math.random())) end\n"
                          "math.randomseed(42.9)  -- read as the C int 42\n"
                          "warn(string.format('%.7f', math.random()))\n"),
              (std::vector<std::string>{"0.0334699", "0.3299642", "0.6906357", "0.4224867", "0.2062651", "0.2501285",
                                        "0.0334699"}));
}

TEST(LuaCompat, RandomRangesFollowTheFormula) {
    const std::vector<std::string> got = warnings_of(
        "math.randomseed(7)\n"
        "for i = 1, 200 do warn(tostring(math.random(10))) end\n"
        "for i = 1, 200 do warn(tostring(math.random(-3, 3))) end\n"
        "warn(tostring(math.random(3.7)))  -- 5.1 truncated to 3\n"
        "warn(math.type(math.random(5)))\n");
    ASSERT_EQ(got.size(), 402u);
    GlibcRandom g(7);
    std::set<long> seen_m, seen_lu;
    for (int i = 0; i < 200; ++i) {
        const long value = std::stol(got[i]);
        EXPECT_EQ(value, static_cast<long>(std::floor(fraction_51(g.next()) * 10)) + 1);
        seen_m.insert(value);
    }
    for (int i = 200; i < 400; ++i) {
        const long value = std::stol(got[i]);
        EXPECT_EQ(value, static_cast<long>(std::floor(fraction_51(g.next()) * 7)) - 3);
        seen_lu.insert(value);
    }
    EXPECT_EQ(seen_m, (std::set<long>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
    EXPECT_EQ(seen_lu, (std::set<long>{-3, -2, -1, 0, 1, 2, 3}));
    EXPECT_EQ(std::stol(got[400]), static_cast<long>(std::floor(fraction_51(g.next()) * 3)) + 1);
    EXPECT_EQ(got[401], "integer");  // prints as 5.1 printed it ("3", not "3.0")
}

TEST(LuaCompat, RandomArgumentErrorsNameTheLine) {
    TempFolder dir;
    const std::pair<std::string, std::string> cases[] = {
        {"math.random(0)", "interval is empty"},
        {"math.random(3, 1)", "interval is empty"},
        {"math.random(1, 2, 3)", "wrong number of arguments"},
        {"math.random('x')", "number expected"},
        {"math.randomseed()", "number expected"},
    };
    for (const auto& [call, message] : cases) {
        const std::string path = dir.write("r.lua", "local x = 1\n" + call + "\n");
        const std::string error = load_error(path);
        EXPECT_EQ(error.rfind(path + ":2: ", 0), 0u) << error;
        EXPECT_NE(error.find(message), std::string::npos) << error;
    }
}

// ---- gr.mesh inline, gr.isodecahedron ----

const NodeDesc& node_named(const SceneDesc& scene, const std::string& name) {
    for (const NodeDesc& node : scene.nodes)
        if (node.name == name) return node;
    throw std::runtime_error("no node " + name);
}

const MeshData& mesh_of(const SceneDesc& scene, const std::string& name) {
    return *scene.meshes.at(node_named(scene, name).mesh);
}

glm::vec3 normal_of(const MeshData& mesh, const glm::uvec3& t) {
    return glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
}

TEST(LuaCompat, InlineMeshIsTheObjMeshWithZeroBasedIndices) {
    TempFolder dir;
    const std::string path = dir.write("s.lua",
        "root = gr.node('root')\n"
        "root:add_child(gr.mesh('quad', {{0,0,0}, {1,0,0}, {1,1,0}, {0,1,0}}, {{0, 1, 2, 3}}))\n"
        "root:add_child(gr.mesh('box', {{-1,-1,-1}, {1,-1,-1}, {1,1,-1}, {-1,1,-1}, {-1,-1,1}, {1,-1,1}, {1,1,1},"
        " {-1,1,1}}, {{4,5,6,7}, {3,2,1,0}, {1,2,6,5}, {0,4,7,3}, {3,7,6,2}, {0,1,5,4}}))\n" +
        std::string(render_line));
    const SceneScript script = load_scene_script(path);  // through the loader process and the wire
    const SceneDesc& scene = *script.renders.at(0).scene;
    const MeshData& quad = mesh_of(scene, "quad");
    EXPECT_EQ(node_named(scene, "quad").kind, NodeKind::mesh);
    ASSERT_EQ(quad.triangles.size(), 2u);
    EXPECT_EQ(quad.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(quad.triangles[1], glm::uvec3(0, 2, 3));
    for (const glm::uvec3& t : quad.triangles) EXPECT_EQ(glm::normalize(normal_of(quad, t)), glm::vec3(0, 0, 1));
    EXPECT_TRUE(quad.texcoords.empty());
    EXPECT_TRUE(quad.path.empty());  // no file for the preview to watch

    // The same box as an OBJ file (1-based) gives the same mesh, and every face points outward.
    const std::shared_ptr<const MeshData> obj = parse_obj_mesh(
        "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
        "f 5 6 7 8\nf 4 3 2 1\nf 2 3 7 6\nf 1 5 8 4\nf 4 8 7 3\nf 1 2 6 5\n", "box.obj");
    const MeshData& box = mesh_of(scene, "box");
    EXPECT_EQ(box.positions, obj->positions);
    EXPECT_EQ(box.triangles, obj->triangles);
    EXPECT_EQ(box.texcoords, obj->texcoords);
    ASSERT_EQ(box.triangles.size(), 12u);
    for (const glm::uvec3& t : box.triangles) {
        const glm::vec3 centre = (box.positions[t.x] + box.positions[t.y] + box.positions[t.z]) / 3.0f;
        EXPECT_GT(glm::dot(normal_of(box, t), centre), 0.0f);
    }
}

TEST(LuaCompat, InlineMeshBadInputNamesTheLine) {
    TempFolder dir;
    const std::string verts = "{{0,0,0}, {1,0,0}, {1,1,0}, {0,1,0}}";
    const std::pair<std::string, std::string> cases[] = {
        {"gr.mesh('m', " + verts + ", {{0, 1, 4}})",
         "gr.mesh: face 1, index 3 is vertex 4, out of range (indices are 0-based: 0..3)"},
        {"gr.mesh('m', " + verts + ", {{0, 1, 2}, {-1, 0, 1}})", "gr.mesh: face 2, index 1 is vertex -1, out of range"},
        {"gr.mesh('m', " + verts + ", {{0, 1}})", "gr.mesh: face 1 must be a list of at least 3 vertex indices, got a table of 2 values"},
        {"gr.mesh('m', " + verts + ", {{0, 1, 'x'}})", "gr.mesh: face 1, index 3 must be a whole number, got string"},
        {"gr.mesh('m', " + verts + ", {{0, 1, 1.5}})", "gr.mesh: face 1, index 3 must be a whole number, got 1.5"},
        {"gr.mesh('m', " + verts + ", {})", "gr.mesh: a mesh needs at least one face"},
        {"gr.mesh('m', " + verts + ", 7)", "gr.mesh: faces must be a table of index lists"},
        {"gr.mesh('m', {{0,0,0}, {1,0}, {1,1,0}}, {{0, 1, 2}})", "gr.mesh: vertex 2 must be {x, y, z}, got a table of 2 values"},
        {"gr.mesh('m', {{0,0,0}, {1,0,'a'}, {1,1,0}}, {{0, 1, 2}})", "gr.mesh: vertex 2: z must be a finite number, got string"},
        {"gr.mesh('m', {{0,0,0}, {1,0,1e300}, {1,1,0}}, {{0, 1, 2}})", "gr.mesh: vertex 2: z must be a finite number within float range"},
        {"gr.mesh('m', {{0,0,0}, {1,0,0/0}, {1,1,0}}, {{0, 1, 2}})", "gr.mesh: vertex 2: z must be a finite number"},
        {"gr.mesh('m', {{0,0,0}, {1,0,0}, {1,1,0}})", "gr.mesh: the inline form needs vertices and faces"},
    };
    for (const auto& [call, message] : cases) {
        const std::string path = dir.write("m.lua", "local x = 1\n" + call + "\n");
        const std::string error = load_error(path);
        EXPECT_EQ(error.rfind(path + ":2: " + message, 0), 0u) << error;
    }
    // A huge triangle count is charged to the script's memory budget before anything is made:
    // 10 000 faces of 1 000 corners share one table (a few KiB of Lua) but make 120 MB of mesh.
    LoadSettings settings;
    settings.memory_limit_bytes = std::size_t(64) << 20;
    const std::string huge = dir.write("huge.lua",
        "local f, faces = {}, {}\nfor i = 1, 1000 do f[i] = i % 3 end\nfor i = 1, 10000 do faces[i] = f end\n"
        "gr.mesh('m', {{0,0,0}, {1,0,0}, {1,1,0}}, faces)\n");
    const std::string error = load_error(huge, settings);
    EXPECT_EQ(error.rfind(huge + ":4: gr.mesh: the scene's memory budget of 64 MiB is used up: the mesh", 0), 0u) << error;
}

TEST(LuaCompat, IsodecahedronIsTheOutwardIcosahedron) {
    TempFolder dir;
    const std::string path = dir.write("s.lua",
        "root = gr.node('root')\nroot:add_child(gr.isodecahedron('ico'))\nroot:add_child(gr.isodecahedron('ico2'))\n" +
        std::string(render_line));
    const SceneScript script = load_scene_script(path);
    const SceneDesc& scene = *script.renders.at(0).scene;
    EXPECT_EQ(node_named(scene, "ico").kind, NodeKind::mesh);
    EXPECT_EQ(node_named(scene, "ico").mesh, node_named(scene, "ico2").mesh);  // one mesh, made once
    const MeshData& mesh = mesh_of(scene, "ico");
    const float phi = 1.618f;
    std::set<std::vector<float>> expected, got;
    for (float a : {1.0f, -1.0f})
        for (float b : {phi, -phi}) {
            expected.insert({0, a, b});
            expected.insert({a, b, 0});
            expected.insert({b, 0, a});
        }
    for (const glm::vec3& p : mesh.positions) got.insert({p.x, p.y, p.z});
    EXPECT_EQ(mesh.positions.size(), 12u);
    EXPECT_EQ(got, expected);
    ASSERT_EQ(mesh.triangles.size(), 20u);
    std::map<std::pair<unsigned, unsigned>, int> directed_edges;
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::vec3 centre = mesh.positions[t.x] + mesh.positions[t.y] + mesh.positions[t.z];
        EXPECT_GT(glm::dot(normal_of(mesh, t), centre), 0.0f);
        for (int k = 0; k < 3; ++k) {
            const unsigned a = t[k], b = t[(k + 1) % 3];
            const glm::vec3 d = mesh.positions[a] - mesh.positions[b];
            EXPECT_NEAR(glm::dot(d, d), 4.0f, 1e-3f);  // every edge has length 2
            ++directed_edges[{a, b}];
        }
    }
    // Closed and consistently oriented: each of the 30 edges is used once in each direction.
    EXPECT_EQ(directed_edges.size(), 60u);
    for (const auto& [edge, count] : directed_edges) {
        EXPECT_EQ(count, 1);
        EXPECT_EQ(directed_edges.count({edge.second, edge.first}), 1u);
    }
    EXPECT_TRUE(mesh.texcoords.empty());
}

// ---- node:render, gr.joint ----

TEST(LuaCompat, NodeRenderIsGrRender) {
    TempFolder dir;
    const std::string args = "'x.png', 32, 16, {1,2,5}, {0,0,-1}, {0,1,0}, 40, {0.1,0.2,0.3}, {l}";
    const std::string path = dir.write("s.lua",
        "root = gr.node('root')\nroot:add_child(gr.sphere('s'))\nl = gr.light({0,5,5}, {1,1,1}, {1,0,0})\n"
        "root:render(" + args + ")\ngr.render(root, " + args + ")\n");
    const SceneScript script = load_scene_script(path);
    ASSERT_EQ(script.renders.size(), 2u);
    const RenderJob &a = script.renders[0], &b = script.renders[1];
    EXPECT_EQ(a.root, b.root);
    EXPECT_EQ(a.scene->nodes.at(a.root).name, "root");
    EXPECT_EQ(a.output, b.output);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, 16);
    EXPECT_EQ(a.camera.eye, b.camera.eye);
    EXPECT_EQ(a.camera.eye, glm::dvec3(1, 2, 5));
    EXPECT_EQ(a.camera.fovy_degrees, b.camera.fovy_degrees);
    EXPECT_EQ(a.ambient, b.ambient);
    EXPECT_EQ(a.lights, b.lights);
    EXPECT_EQ(a.lights, std::vector<int>{0});
    EXPECT_EQ(a.scene->nodes.size(), b.scene->nodes.size());
    EXPECT_EQ(a.where.line, 4);
    EXPECT_EQ(b.where.line, 5);
}

TEST(LuaCompat, JointActsAsANode) {
    TempFolder dir;
    const std::string path = dir.write("s.lua",
        "m = gr.material({1,0,0}, {0,0,0}, 0)\n"
        "root = gr.node('root')\n"
        "j = gr.joint('j', {-10, 0, 10}, {-5, 0, 5})\n"
        "root:add_child(j)\nj:add_child(gr.sphere('s'))\nj:translate(1, 2, 3)\nj:rotate('x', 30)\nj:scale(2, 2, 2)\n"
        "j:set_material(m)\n"
        "j:render('j.png', 8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0,0,0}, {})\n" + std::string(render_line));
    const SceneScript script = load_scene_script(path);
    ASSERT_EQ(script.renders.size(), 2u);
    const SceneDesc& scene = *script.renders[1].scene;
    const NodeDesc& j = node_named(scene, "j");
    EXPECT_EQ(j.kind, NodeKind::group);
    ASSERT_EQ(j.children.size(), 1u);
    EXPECT_EQ(scene.nodes[j.children[0]].name, "s");
    EXPECT_EQ(node_named(scene, "root").children, std::vector<int>{script.renders[0].root});
    ASSERT_EQ(j.transforms.size(), 3u);
    EXPECT_EQ(j.transforms[0].amount, glm::dvec3(1, 2, 3));
    EXPECT_EQ(j.transforms[1].degrees, 30.0);
    EXPECT_EQ(j.material, 0);
    EXPECT_EQ(script.renders[0].scene->nodes.at(script.renders[0].root).name, "j");

    const std::string bad = dir.write("bad.lua", "local x = 1\ngr.joint('j', {1, 2}, {0, 0, 0})\n");
    EXPECT_EQ(load_error(bad), bad + ":2: gr.joint: x range must be 3 numbers, got a table of 2 values");
}

}  // namespace
}  // namespace caustica
