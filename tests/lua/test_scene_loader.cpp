// Tests of the Lua scene loader (core/lua) and the OBJ loader: the course scenes, snapshots,
// options, the 5.1 module system, the sandbox, every class of bad input and the limits.
#include "core/lua/scene_loader.h"
#include "core/geometry/mesh_obj.h"
#include "core/io/png_io.h"
#include "tests/course_scenes.h"
#include "tests/scene_test_helpers.h"
#include "tests/temp_folder.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>

namespace caustica {
namespace {

namespace fs = std::filesystem;

using testing::TempFolder;

using testing::load_error;

const NodeDesc& node_named(const SceneDesc& scene, const std::string& name) {
    for (const NodeDesc& node : scene.nodes)
        if (node.name == name) return node;
    throw std::runtime_error("no node " + name);
}

int index_of(const SceneDesc& scene, const std::string& name) {
    return static_cast<int>(&node_named(scene, name) - scene.nodes.data());
}

int parents_of(const SceneDesc& scene, int child) {
    int count = 0;
    for (const NodeDesc& node : scene.nodes)
        for (int c : node.children) count += c == child;
    return count;
}

const char* render_line = "gr.render(root, 'out.png', 64, 48, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0.1,0.1,0.1}, {})\n";

// ---- the course scenes ----

struct CourseScene {
    const char* file;
    int lights;
    std::vector<std::pair<std::string, size_t>> mesh_triangles;  // mesh node -> triangles
};

TEST(SceneLoader, EveryCourseSceneLoads) {
    CAUSTICA_SKIP_WITHOUT_CS488();
    const std::vector<CourseScene> scenes = {
        {"hier", 2, {{"plane", 2}, {"poly", 36}}},
        {"macho-cows", 1, {{"cow", 5804}, {"plane", 2}, {"buckyball", 116}}},
        {"nonhier", 2, {{"dodec", 60}}},
        {"simple-cows", 1, {{"plane", 2}, {"buckyball", 116}}},
        {"simple", 2, {}},
    };
    for (const CourseScene& expected : scenes) {
        SCOPED_TRACE(expected.file);
        LoadSettings settings;
        settings.base_options.a4 = true;
        const std::string path = testing::cs488_file(std::string(expected.file) + ".lua");
        const SceneScript script = load_scene_script(path, settings);
        ASSERT_EQ(script.renders.size(), 1u);
        const RenderJob& job = script.renders[0];
        EXPECT_EQ(job.output, std::string(expected.file) + ".png");
        EXPECT_EQ(job.width, 256);
        EXPECT_EQ(job.height, 256);
        EXPECT_TRUE(job.options.a4);
        EXPECT_EQ(job.lights.size(), static_cast<size_t>(expected.lights));
        EXPECT_EQ(job.camera.fovy_degrees, 50.0);
        EXPECT_EQ(job.where.file, path);
        for (const auto& [name, triangles] : expected.mesh_triangles) {
            const NodeDesc& mesh = node_named(*job.scene, name);
            ASSERT_EQ(mesh.kind, NodeKind::mesh);
            EXPECT_EQ(job.scene->meshes.at(mesh.mesh)->triangles.size(), triangles) << name;
        }
        EXPECT_EQ(job.scene->meshes.size(), expected.mesh_triangles.size());  // one MeshData per file
    }
}

TEST(SceneLoader, HierarchyTransformsAndInstancing) {
    CAUSTICA_SKIP_WITHOUT_CS488();
    const SceneScript script = load_scene_script(testing::cs488_file("macho-cows.lua"));
    const SceneDesc& scene = *script.renders.at(0).scene;
    EXPECT_EQ(script.renders[0].root, index_of(scene, "scene"));
    const NodeDesc& cow = node_named(scene, "cow");
    ASSERT_EQ(cow.transforms.size(), 3u);  // translate, scale, translate: in call order
    EXPECT_EQ(cow.transforms[0].kind, TransformOp::Kind::translate);
    EXPECT_EQ(cow.transforms[0].amount, glm::dvec3(0.0, 3.637, 0.0));
    EXPECT_EQ(cow.transforms[1].kind, TransformOp::Kind::scale);
    EXPECT_DOUBLE_EQ(cow.transforms[1].amount.x, 2.0 / (2.76 + 3.637));
    EXPECT_EQ(cow.transforms[2].amount, glm::dvec3(0.0, -1.0, 0.0));
    EXPECT_EQ(cow.transforms[0].where.line, 50);
    EXPECT_EQ(parents_of(scene, index_of(scene, "cow")), 3);  // instanced under cow1..cow3
    EXPECT_EQ(parents_of(scene, index_of(scene, "arc")), 7);  // inst + arc1..arc6
    const NodeDesc& cow2 = node_named(scene, "cow2");
    ASSERT_EQ(cow2.transforms.size(), 3u);
    EXPECT_EQ(cow2.transforms[1].kind, TransformOp::Kind::rotate);
    EXPECT_EQ(cow2.transforms[1].axis, 1);
    EXPECT_EQ(cow2.transforms[1].degrees, 180.0);
    const NodeDesc& p1 = node_named(scene, "p1");
    EXPECT_EQ(p1.kind, NodeKind::nh_box);
    EXPECT_EQ(p1.material, 0);
    EXPECT_EQ(scene.materials.at(2).kd, glm::dvec3(0.84, 0.6, 0.53));
    EXPECT_EQ(scene.materials.at(2).shininess, 20.0);
    EXPECT_EQ(scene.lights.at(0).position, glm::dvec3(200, 202, 430));
    EXPECT_EQ(script.renders[0].camera.eye, glm::dvec3(0, 2, 30));
    EXPECT_EQ(script.renders[0].ambient, glm::dvec3(0.4));
}

// ---- snapshots, options, the rest of the API ----

TEST(SceneLoader, EachRenderIsASnapshot) {
    TempFolder dir;
    const std::string path = dir.write("scene.lua", R"(m = gr.material({1,0,0}, {0,0,0}, 0)
root = gr.node('root')
s = gr.sphere('s')
root:add_child(s)
l = gr.light({0,0,10}, {1,1,1}, {1,0,0})
gr.render(root, 'a.png', 64, 32, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0.1,0.1,0.1}, {l})
s:set_material(m)
s:translate(1, 2, 3)
gr.set_miss_colour({0.2, 0.3, 0.4})
root:render('b.png', 16, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 30, {0,0,0}, {})
)");
    const SceneScript script = load_scene_script(path);
    ASSERT_EQ(script.renders.size(), 2u);
    const RenderJob& a = script.renders[0];
    const RenderJob& b = script.renders[1];
    EXPECT_NE(a.scene, b.scene);
    EXPECT_EQ(node_named(*a.scene, "s").material, -1);
    EXPECT_TRUE(node_named(*a.scene, "s").transforms.empty());
    EXPECT_EQ(node_named(*b.scene, "s").material, 0);
    ASSERT_EQ(node_named(*b.scene, "s").transforms.size(), 1u);
    EXPECT_EQ(node_named(*b.scene, "s").transforms[0].amount, glm::dvec3(1, 2, 3));
    EXPECT_EQ(a.miss_colour, glm::dvec3(1.0));  // the default miss colour is white
    EXPECT_EQ(b.miss_colour, glm::dvec3(0.2, 0.3, 0.4));
    EXPECT_EQ(a.output, "a.png");
    EXPECT_EQ(b.output, "b.png");
    EXPECT_EQ(a.width, 64);
    EXPECT_EQ(a.height, 32);
    EXPECT_EQ(a.lights, std::vector<int>{0});
    EXPECT_TRUE(b.lights.empty());
    EXPECT_EQ(a.where.line, 6);
    EXPECT_EQ(b.where.line, 10);
    EXPECT_EQ(b.camera.fovy_degrees, 30.0);
}

TEST(SceneLoader, OptionsAccumulateFromTheBase) {
    TempFolder dir;
    const std::string path = dir.write("scene.lua", std::string("root = gr.node('root')\ngr.option('--aa-grid 5')\n") +
                                                        render_line + "gr.option('-S --a4')\n" + render_line +
                                                        "gr.option('--aa-grid=2')\n");
    LoadSettings settings;
    settings.base_options.threads = 3;
    const SceneScript script = load_scene_script(path, settings);
    ASSERT_EQ(script.renders.size(), 2u);
    EXPECT_EQ(script.renders[0].options.aa_grid, 5);
    EXPECT_FALSE(script.renders[0].options.stats);
    EXPECT_FALSE(script.renders[0].options.a4);
    EXPECT_EQ(script.renders[1].options.aa_grid, 5);
    EXPECT_TRUE(script.renders[1].options.stats);
    EXPECT_TRUE(script.renders[1].options.a4);
    EXPECT_EQ(script.renders[0].options.threads, 3);
    EXPECT_EQ(script.renders[1].options.threads, 3);
}

TEST(SceneLoader, MaterialsTexturesLightsAndCsg) {
    TempFolder dir;
    write_png_atomic(dir.file("wood.png"), Image(4, 2), PixelEncoding::clamped_linear);
    dir.write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n");
    const std::string path = dir.write("scene.lua", R"(glass = gr.material({0,0,0}, {1,1,1}, 100)
glass:set_ri(1.5)
mirror = gr.material({0.1,0.1,0.1}, {0.9,0.9,0.9}, 50)
mirror:set_reflective()
inside = gr.air()
t = gr.texture('wood.png')
t:remapt('cubetop')
b = gr.bumpmap('ripple')
b:remap('cyltop')
mirror:set_texture(gr.texture('redcheck'))
mirror:set_bumpmap(b)
glass:set_texture(t)
l = gr.light({1,2,3}, {0.5,0.5,0.5}, {1,0.5,0.25})
l:set_radius(0.3)
root = gr.node('root')
cup = gr.union('cup', gr.cylinder('c', glass), gr.cone('k'))
root:add_child(gr.difference(cup, gr.nh_sphere('hole', {0,1,0}, 0.5)))
root:add_child(gr.intersection(gr.cube('a'), gr.mesh('m1', 'm.obj')))
root:add_child(gr.mesh('m2', './m.obj'))
j = gr.joint('j', {-10, 0, 10}, {0, 0, 0})
j:rotate('z', -30)
warn('hello ', 'there')
gr.render(root, 'out.png', 10, 10, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0,0,0}, {l})
)");
    const SceneScript script = load_scene_script(path);
    ASSERT_EQ(script.renders.size(), 1u);
    const SceneDesc& scene = *script.renders[0].scene;
    ASSERT_EQ(scene.materials.size(), 3u);
    EXPECT_EQ(scene.materials[0].refractive_index, 1.5);
    EXPECT_TRUE(scene.materials[1].reflective);
    EXPECT_TRUE(scene.materials[2].air);
    ASSERT_EQ(scene.textures.size(), 3u);
    EXPECT_EQ(scene.textures[0].source, (dir.path() / "wood.png").string());
    EXPECT_FALSE(scene.textures[0].procedural);
    EXPECT_EQ(scene.textures[0].remap, "cubetop");
    EXPECT_EQ(scene.textures[1].source, "sinewaves");
    EXPECT_TRUE(scene.textures[1].procedural);
    EXPECT_EQ(scene.textures[1].remap, "cyltop");
    EXPECT_EQ(scene.materials[1].texture, 2);
    EXPECT_EQ(scene.materials[1].bumpmap, 1);
    EXPECT_EQ(scene.materials[0].texture, 0);
    EXPECT_EQ(scene.lights.at(0).radius, 0.3);
    EXPECT_EQ(scene.lights[0].falloff, glm::dvec3(1, 0.5, 0.25));
    const NodeDesc& cup = node_named(scene, "cup");
    EXPECT_EQ(cup.kind, NodeKind::csg_union);
    EXPECT_EQ(cup.csg_left, index_of(scene, "c"));
    EXPECT_EQ(cup.csg_right, index_of(scene, "k"));
    EXPECT_EQ(node_named(scene, "c").material, 0);
    EXPECT_EQ(node_named(scene, "difference").csg_left, index_of(scene, "cup"));
    EXPECT_EQ(node_named(scene, "intersection").kind, NodeKind::csg_intersection);
    EXPECT_EQ(node_named(scene, "hole").position, glm::dvec3(0, 1, 0));
    EXPECT_EQ(node_named(scene, "hole").size, 0.5);
    ASSERT_EQ(scene.meshes.size(), 1u);  // m.obj and ./m.obj are one file
    EXPECT_EQ(node_named(scene, "m2").mesh, 0);
    EXPECT_EQ(scene.meshes[0]->triangles.size(), 2u);
    EXPECT_EQ(node_named(scene, "j").kind, NodeKind::group);
    EXPECT_EQ(node_named(scene, "j").transforms.at(0).axis, 2);
    ASSERT_EQ(script.warnings.size(), 1u);
    EXPECT_EQ(script.warnings[0], path + ":22: hello there");
}

// ---- Lua 5.1 modules and the sandbox ----

TEST(SceneLoader, ModulesRequireAndMainDetection) {
    TempFolder dir;
    dir.write("colours.lua", "module(..., package.seeall)\nred = gr.material({1,0,0}, {0,0,0}, 0)\n");
    dir.write("include/shapes.lua", R"(module(..., package.seeall)
main = debug.getinfo(2) == nil
function ball(m) local s = gr.sphere('ball'); s:set_material(m); return s end
)");
    const std::string path = dir.write("scene.lua", R"(module(..., package.seeall)
require 'colours'
local shapes = require 'shapes'
assert(require('shapes') == shapes and shapes._NAME == 'shapes')
assert(shapes.main == false and colours.red ~= nil)
assert(require('os').getenv == os.getenv and require('string').format('%d', 7) == '7')
root = gr.node('root')
root:add_child(shapes.ball(colours.red))
if debug.getinfo(2) == nil then
  gr.render(root, 'out.png', 8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0,0,0}, {})
end
)");
    const SceneScript script = load_scene_script(path);
    ASSERT_EQ(script.renders.size(), 1u);
    EXPECT_EQ(node_named(*script.renders[0].scene, "ball").material, 0);
    EXPECT_EQ(script.renders[0].root, index_of(*script.renders[0].scene, "root"));
}

TEST(SceneLoader, SandboxReadsOnlyTheSceneFolder) {
    TempFolder outside;
    const std::string secret = outside.write("secret.txt", "secret\n");
    TempFolder dir;
    dir.write("data.txt", "first\nsecond\n");
    dir.write("sub/x.txt", "x\n");
    fs::create_symlink(secret, dir.path() / "link_out");
    const std::string escape = "../" + outside.path().filename().string() + "/secret.txt";
    const std::string path = dir.write("scene.lua", R"(local f = assert(io.open('data.txt', 'r'))
local lines = {}
for line in f:lines() do lines[#lines + 1] = line end
f:close()
assert(#lines == 2 and lines[2] == 'second')
local g = io.open('sub/../data.txt'); assert(g:read('l') == 'first'); g:close()
local count = 0; for l in io.lines('data.txt') do count = count + 1 end; assert(count == 2)
assert(io.open('/etc/passwd') == nil)
assert(io.open(ESCAPE) == nil)
assert(io.open('link_out') == nil)
assert(not pcall(io.lines, '/etc/passwd'))
assert(not pcall(io.open, 'data.txt', 'w'))
assert(not pcall(io.open, 'new.txt', 'a'))
assert(not pcall(io.open, 'data.txt', 'r+'))
assert(io.popen == nil and io.output == nil and io.input == nil and io.read == nil and io.tmpfile == nil)
assert(os.execute == nil and os.remove == nil and os.rename == nil and os.exit == nil and os.tmpname == nil)
assert(type(os.clock()) == 'number' and type(os.time()) == 'number' and type(os.date('%Y')) == 'string')
assert(os.getenv('CAUSTICA_SURELY_UNSET_VARIABLE_42') == nil)
assert(dofile == nil and loadfile == nil and string.dump == nil and package.loadlib == nil)
assert(debug.sethook == nil and debug.setupvalue == nil and debug.traceback ~= nil)
local fn, message = load('\27Lua\84\0binary')
assert(fn == nil and message:find('binary'))
assert(load('\27Lua\84\0binary', 'x', 'b') == nil)
assert(load('return 1 + 1')() == 2)
assert(unpack({4, 5}) == 4 and math.pow(2, 3) == 8)
assert(not pcall(setmetatable, {}, {__gc = function() while true do end end}))
assert(getmetatable(setmetatable({}, {__index = {a = 1}})).__index.a == 1)
)");
    std::string text;
    {
        std::ifstream in(path);
        text.assign(std::istreambuf_iterator<char>(in), {});
    }
    text.replace(text.find("ESCAPE"), 6, "'" + escape + "'");
    dir.write("scene.lua", text);
    const SceneScript script = load_scene_script(path);
    EXPECT_TRUE(script.renders.empty());
    EXPECT_FALSE(fs::exists(dir.path() / "new.txt"));
}

// ---- bad input: every error names file:line and the call ----

struct BadInput {
    int line;              // of the offending call
    std::string script;    // after the prelude "-- scene\nroot = gr.node('root')\n"
    std::string expected;  // the message after "file:line: "
};

TEST(SceneLoader, BadInputIsReportedWhereItIsWritten) {
    const std::string render_head = "gr.render(root, 'out.png', ";
    const std::vector<BadInput> cases = {
        {3, "x = = 1", "unexpected symbol near '='"},
        {4, "local t = nil\nprint(t.x)", "attempt to index a nil value"},
        {3, "gr.material({1,0}, {0,0,0}, 10)", "gr.material: kd must be 3 numbers"},
        {3, "gr.material({1,0,0}, {0,-1,0}, 10)", "gr.material: ks must not be negative"},
        {3, "gr.nh_sphere('s', {0,0,0})", "gr.nh_sphere: expected 3 arguments (name, {x,y,z}, radius), got 2"},
        {3, "gr.nh_sphere('s', {0,0,0}, -1)", "gr.nh_sphere: radius must be positive, got -1"},
        {3, "gr.nh_box('b', {0,0,0}, 0)", "gr.nh_box: size must be positive, got 0"},
        {4, "\ngr.light({0/0, 0, 0}, {1,1,1}, {1,0,0})", "gr.light: position must be 3 finite numbers"},
        {3, "gr.light({0,0,0}, {1,1,1}, {1,-1,0})", "gr.light: falloff must not be negative"},
        {3, "gr.light({0,0,0}, {1,1,1}, {0,0,0})", "gr.light: falloff must not be all zero"},
        {3, "gr.light({0,0,0}, {1,1,1}, {1,0,0}):set_radius(-2)", "light:set_radius: radius must not be negative"},
        {3, "root:translate(1/0, 0, 0)", "node:translate: x must be a finite number, got inf"},
        {3, "root:scale(1, 0, 1)", "node:scale: factor 0 makes the transform singular"},
        {3, "root:rotate('w', 10)", "node:rotate: axis must be 'x', 'y' or 'z', got 'w'"},
        {3, "root.translate(1, 2, 3)", "node:translate: expected a node before ':'"},
        {3, "gr.mesh('cow', 'nocow.obj')", "gr.mesh: cannot open 'nocow.obj' ("},
        {3, "gr.texture('wood.png')", "gr.texture: cannot open 'wood.png' ("},
        {3, "gr.texture('fake.png')", "gr.texture: 'fake.png' ("},
        {3, "gr.bumpmap('sinewaves'):remap('cubeside')", "texture:remap: unknown remap mode 'cubeside'"},
        {3, "gr.material({1,1,1}, {0,0,0}, 1):set_ri(0)", "material:set_ri: refractive index must be positive, got 0"},
        {3, "gr.material({1,1,1}, {0,0,0}, 1):set_texture(gr.bumpmap('sinewaves'))",
         "material:set_texture: texture must be a texture (from gr.texture), got a bump map"},
        {5, "a = gr.node('a')\nroot:add_child(a)\na:add_child(root)",
         "node:add_child: adding 'root' under 'a' would make a cycle"},
        {3, "root:add_child(root)", "node:add_child: adding 'root' under 'root' would make a cycle"},
        // A chain built from its leaf up, closed at the leaf.
        {4, "a = gr.node('a'); b = gr.node('b'); b:add_child(a); c = gr.node('c'); c:add_child(b)\na:add_child(c)",
         "node:add_child: adding 'c' under 'a' would make a cycle"},
        // Through a CSG operand below a subtree instanced twice.
        {5, "a = gr.node('a'); u = gr.union(a, gr.sphere('s'))\nb = gr.node('b'); b:add_child(u); b:add_child(u); "
            "root:add_child(b)\na:add_child(root)",
         "node:add_child: adding 'root' under 'a' would make a cycle"},
        {3, "gr.union(gr.sphere('s'), gr.material({1,1,1}, {0,0,0}, 1))",
         "gr.union: the second operand must be a node, got a material"},
        {3, "gr.render(gr.air(), 'o.png', 8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0,0,0}, {})",
         "gr.render: root must be a node"},
        {3, render_head + "8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0,0,0}, {root})",
         "gr.render: lights[1] must be a light (from gr.light), got a node"},
        {3, render_head + "0, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0,0,0}, {})", "gr.render: width must be positive"},
        {3, render_head + "8, 40000, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0,0,0}, {})",
         "gr.render: height 40000 is larger than the maximum of 32768"},
        {3, render_head + "20000, 20000, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0,0,0}, {})",
         "gr.render: an image of 20000 x 20000 pixels is larger"},
        {3, render_head + "8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 180, {0,0,0}, {})", "gr.render: fovy must be between"},
        {3, render_head + "8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 0, {0,0,0}, {})", "gr.render: fovy must be between"},
        {3, render_head + "8, 8, {0,0,5}, {0,0,0}, {0,1,0}, 45, {0,0,0}, {})",
         "gr.render: view must not be zero-length"},
        {3, render_head + "8, 8, {0,0,5}, {0,2,0}, {0,1,0}, 45, {0,0,0}, {})",
         "gr.render: up must not be parallel to view"},
        {3, render_head + "8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0,0,0})",
         "gr.render: expected 10 arguments"},
        {3, "root:render('o.png', 8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 45, {0,0,0}, 7)",
         "node:render: lights must be a table of lights, got a number"},
        {3, "gr.option('--aa-gird 3')", "gr.option: unknown option '--aa-gird' (did you mean --aa-grid?)"},
        {3, "gr.option('--aa-grid -1')", "gr.option: --aa-grid: -1 is out of range"},
        {3, "require 'nowhere'", "require: module 'nowhere' not found"},
        {4, "local ok = pcall(error, 'x')\ngr.sphere(42)", "gr.sphere: name must be a string, got a number (42)"},
    };
    for (const BadInput& bad : cases) {
        TempFolder dir;
        dir.write("fake.png", "not a png");
        const std::string path = dir.write("scene.lua", "-- scene\nroot = gr.node('root')\n" + bad.script + "\n");
        const std::string expected = path + ":" + std::to_string(bad.line) + ": " + bad.expected;
        const std::string message = load_error(path);
        EXPECT_EQ(message.substr(0, expected.size()), expected) << bad.script;
    }
}

TEST(SceneLoader, ErrorsInsideRequiredFilesNameThatFile) {
    TempFolder dir;
    const std::string module = dir.write("include/bad.lua", "local x = 1\ngr.material({1,0,0}, {0,0,0})\n");
    const std::string path = dir.write("scene.lua", "require 'bad'\n");
    EXPECT_EQ(load_error(path), module + ":2: gr.material: expected 3 arguments ({kd}, {ks}, shininess), got 2");
}

TEST(SceneLoader, NoRenderIsNotALoaderError) {
    TempFolder dir;
    EXPECT_TRUE(load_scene_script(dir.write("scene.lua", "x = 1\n")).renders.empty());
    EXPECT_NE(load_error((dir.path() / "missing.lua").string()).find("cannot open"), std::string::npos);
}

// ---- limits ----

TEST(SceneLoader, TimeoutNamesTheLineItStopped) {
    TempFolder dir;
    const std::string path = dir.write("scene.lua", "-- spin\nlocal x = 0\nwhile true do end\n");
    LoadSettings settings;
    settings.timeout_seconds = 0.5;
    const auto start = std::chrono::steady_clock::now();
    EXPECT_EQ(load_error(path, settings), path + ":3: script stopped after 0.5 s (--script-timeout)");
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
              caustica::testing::time_bound(5.0));

    // A script cannot catch the stop and carry on.
    const std::string stubborn =
        dir.write("stubborn.lua", "while true do\n  pcall(function() while true do end end)\nend\n");
    EXPECT_NE(load_error(stubborn, settings).find("script stopped after 0.5 s"), std::string::npos);
}

TEST(SceneLoader, MemoryLimitStopsTheScript) {
    TempFolder dir;
    const std::string path = dir.write("scene.lua", "local t = {}\nfor i = 1, 1e9 do t[i] = {i} end\n");
    LoadSettings settings;
    settings.memory_limit_bytes = std::size_t(64) << 20;
    EXPECT_EQ(load_error(path, settings), path + ":2: script exceeded the memory limit of 64 MiB (Lua heap and "
                                                 "scene data; --script-memory sets it)");
    const std::string big = dir.write("big.lua", "local s = string.rep('x', 100 * 1024 * 1024)\n");
    EXPECT_NE(load_error(big, settings).find("script exceeded the memory limit of 64 MiB"), std::string::npos);
}

TEST(SceneLoader, CancelStopsPromptly) {
    TempFolder dir;
    const std::string path = dir.write("scene.lua", "while true do end\n");
    std::atomic<bool> cancel{false};
    LoadSettings settings;
    settings.timeout_seconds = 0;
    settings.cancel = &cancel;
    std::thread canceller([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        cancel = true;
    });
    EXPECT_THROW(load_scene_script(path, settings), ScriptCancelled);
    canceller.join();
    EXPECT_THROW(load_scene_script(path, settings), ScriptCancelled);  // already set: does not start
}

// ---- OBJ loading ----

TEST(MeshObj, PolygonsAreFannedWithCornerTexcoords) {
    TempFolder dir;
    const auto mesh = load_obj_mesh(dir.write("quad.obj", R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0.5 1.5 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
f 1/1 2/2 3/3 4/4
f 4 3 5
)"));
    ASSERT_EQ(mesh->positions.size(), 5u);
    ASSERT_EQ(mesh->triangles.size(), 3u);
    EXPECT_EQ(mesh->triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(mesh->triangles[1], glm::uvec3(0, 2, 3));
    EXPECT_EQ(mesh->triangles[2], glm::uvec3(3, 2, 4));
    ASSERT_EQ(mesh->texcoords.size(), 9u);
    EXPECT_EQ(mesh->texcoords[4], glm::vec2(1, 1));
    EXPECT_EQ(mesh->texcoords[5], glm::vec2(0, 1));
    EXPECT_EQ(mesh->texcoords[8], glm::vec2(0, 0));  // a face without texcoords gets zeros

    const auto plain = load_obj_mesh(dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n"));
    EXPECT_TRUE(plain->texcoords.empty());
}

TEST(MeshObj, TheCourseCowLoads) {
    CAUSTICA_SKIP_WITHOUT_CS488();
    const auto cow = load_obj_mesh(testing::cs488_file("cow.obj"));
    EXPECT_EQ(cow->positions.size(), 2903u);
    EXPECT_EQ(cow->triangles.size(), 5804u);
}

TEST(MeshObj, BadFilesAreInputErrors) {
    TempFolder dir;
    // Errors name the file (as given) and the line: the temporary folder is cut off here.
    auto error_of = [&](const std::string& text) {
        const std::string path = dir.write("bad.obj", text);
        try {
            load_obj_mesh(path);
        } catch (const InputError& e) {
            const std::string message = e.what();
            return message.rfind(path, 0) == 0 ? "bad.obj" + message.substr(path.size()) : message;
        }
        return std::string("(no error)");
    };
    EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\n"), "bad.obj: no triangles (the file has no faces with 3 or more vertices)");
    EXPECT_EQ(error_of("v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
              "bad.obj:2: coordinate 'nan' is not a finite number");
    EXPECT_EQ(error_of("v 0 0 1e39\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), "bad.obj:1: coordinate '1e39' is out of range");
    EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), "bad.obj:4: face index 9 is out of range (1..3)");
    EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), "bad.obj:4: face index 0 is out of range (1..3)");
    EXPECT_THROW(load_obj_mesh((dir.path() / "none.obj").string()), InputError);
}

}  // namespace
}  // namespace caustica
