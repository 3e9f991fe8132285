// The node half of the gr API: primitives, meshes, CSG, hierarchy and transforms.
// Transforms are recorded in call order; the renderer composes them under the convention in force.
#include "core/lua/lua_context.h"
#include "core/lua/scene_files.h"
#include "core/geometry/mesh_obj.h"

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdint>

namespace caustica::scene_lua {
namespace {

int add_node(LoaderContext& ctx, NodeKind kind, std::string name, SourceLocation where) {
    charge_append(ctx, ctx.scene.nodes, name.capacity() + where.file.capacity(), "scene nodes");
    // The cycle check's per-node state (not in the scene's snapshots): charged as its buffer grows.
    if (ctx.node_walk_mark.size() == ctx.node_walk_mark.capacity())
        charge_memory(ctx, std::max<std::size_t>(1, ctx.node_walk_mark.capacity()) * (sizeof(std::uint32_t) + 1),
                      "scene nodes");
    NodeDesc node;
    node.name = std::move(name);
    node.kind = kind;
    node.where = std::move(where);
    ctx.scene.nodes.push_back(std::move(node));
    ctx.node_is_held.push_back(false);
    ctx.node_walk_mark.push_back(0);
    return static_cast<int>(ctx.scene.nodes.size()) - 1;
}

/// True when `target` is `from` or below it (children and CSG operands). The walk costs what lies
/// below `from`, not the size of the scene: each walk has a number, and a node it has seen carries
/// that number, so nothing is cleared between walks and shared subtrees (instances) are walked once.
bool reaches(LoaderContext& ctx, int from, int target) {
    if (++ctx.node_walk == 0) {  // the numbers wrapped around: forget every mark
        std::fill(ctx.node_walk_mark.begin(), ctx.node_walk_mark.end(), 0u);
        ctx.node_walk = 1;
    }
    const std::uint32_t walk = ctx.node_walk;
    std::vector<int> stack{from};
    while (!stack.empty()) {
        const int index = stack.back();
        stack.pop_back();
        if (index == target) return true;
        if (index < 0 || ctx.node_walk_mark[static_cast<std::size_t>(index)] == walk) continue;
        ctx.node_walk_mark[static_cast<std::size_t>(index)] = walk;
        const NodeDesc& node = ctx.scene.nodes[static_cast<std::size_t>(index)];
        stack.insert(stack.end(), node.children.begin(), node.children.end());
        if (node.csg_left >= 0) stack.push_back(node.csg_left);
        if (node.csg_right >= 0) stack.push_back(node.csg_right);
    }
    return false;
}

CallResult named_node(lua_State* L, LoaderContext& ctx, NodeKind kind) {
    expect_arguments(L, 1, 1, 1, "name");
    std::string name = string_arg(L, 1, "name");
    return CallResult::of(HandleKind::node, add_node(ctx, kind, std::move(name), caller_location(L)));
}

CallResult gr_node(lua_State* L, LoaderContext& ctx) { return named_node(L, ctx, NodeKind::group); }
CallResult gr_sphere(lua_State* L, LoaderContext& ctx) { return named_node(L, ctx, NodeKind::sphere); }
CallResult gr_cube(lua_State* L, LoaderContext& ctx) { return named_node(L, ctx, NodeKind::cube); }

CallResult gr_joint(lua_State* L, LoaderContext& ctx) {
    expect_arguments(L, 1, 3, 3, "name, {xmin, xinit, xmax}, {ymin, yinit, ymax}");
    std::string name = string_arg(L, 1, "name");
    vec3_arg(L, 2, "x range");  // validated, then ignored: a joint acts as a plain node
    vec3_arg(L, 3, "y range");
    return CallResult::of(HandleKind::node, add_node(ctx, NodeKind::group, std::move(name), caller_location(L)));
}

/// gr.cylinder and gr.cone: a name and an optional material.
CallResult primitive_with_material(lua_State* L, LoaderContext& ctx, NodeKind kind) {
    expect_arguments(L, 1, 1, 2, "name [, material]");
    std::string name = string_arg(L, 1, "name");
    int material = -1;
    if (!lua_isnoneornil(L, 2)) material = handle_arg(L, 2, HandleKind::material, "material");
    const int index = add_node(ctx, kind, std::move(name), caller_location(L));
    ctx.scene.nodes[index].material = material;
    return CallResult::of(HandleKind::node, index);
}

CallResult gr_cylinder(lua_State* L, LoaderContext& ctx) { return primitive_with_material(L, ctx, NodeKind::cylinder); }
CallResult gr_cone(lua_State* L, LoaderContext& ctx) { return primitive_with_material(L, ctx, NodeKind::cone); }

/// gr.nh_sphere and gr.nh_box: a name, a point and a positive size.
CallResult positioned_primitive(lua_State* L, LoaderContext& ctx, NodeKind kind, const char* signature,
                                const char* size_name) {
    expect_arguments(L, 1, 3, 3, signature);
    std::string name = string_arg(L, 1, "name");
    const glm::dvec3 position = vec3_arg(L, 2, kind == NodeKind::nh_sphere ? "centre" : "corner");
    const double size = number_arg(L, 3, size_name);
    if (size <= 0.0)
        throw InputError(std::string(size_name) + " must be positive, got " + format_number(size));
    const int index = add_node(ctx, kind, std::move(name), caller_location(L));
    ctx.scene.nodes[index].position = position;
    ctx.scene.nodes[index].size = size;
    return CallResult::of(HandleKind::node, index);
}

CallResult gr_nh_sphere(lua_State* L, LoaderContext& ctx) {
    return positioned_primitive(L, ctx, NodeKind::nh_sphere, "name, {x,y,z}, radius", "radius");
}
CallResult gr_nh_box(lua_State* L, LoaderContext& ctx) {
    return positioned_primitive(L, ctx, NodeKind::nh_box, "name, {x,y,z}, size", "size");
}

/// Adds a mesh to the scene (its data already charged) and returns its index.
int add_mesh(LoaderContext& ctx, std::shared_ptr<const MeshData> mesh) {
    charge_append(ctx, ctx.scene.meshes, 0, "the scene's mesh list");
    ctx.scene.meshes.push_back(std::move(mesh));
    return static_cast<int>(ctx.scene.meshes.size()) - 1;
}

/// gr.mesh(name, 'file.obj'): the OBJ reader; the same file named twice is read once.
int obj_mesh(LoaderContext& ctx, const std::string& as_written) {
    const SceneFile file = open_scene_file(ctx, as_written);
    const std::pair<std::uint64_t, std::uint64_t> identity{file.device, file.inode};
    if (auto cached = ctx.mesh_cache.find(identity); cached != ctx.mesh_cache.end()) return cached->second;
    std::shared_ptr<const MeshData> data;
    {
        const std::string text = read_scene_file(ctx, file, "the mesh file");
        data = parse_obj_mesh(text, as_written, file.path);
        release_memory(ctx, text.size());  // the text goes; the mesh is charged instead
    }
    charge_memory(ctx, mesh_bytes(*data), "the mesh");
    const int mesh = add_mesh(ctx, std::move(data));
    ctx.mesh_cache.emplace(identity, mesh);
    return mesh;
}

/// Stops a long walk over a script's table every 4096 items when the time limit or the cancel
/// flag says so (the script's error is then ctx.stop_message).
void check_limits(LoaderContext& ctx, std::size_t item) {
    if ((item & 0xfff) == 0 && limits_reached(ctx)) throw InputError(ctx.stop_message);
}

/// The length of the table at stack index `index` ("vertices must be a table of {x, y, z}, ...").
std::size_t list_length(lua_State* L, int index, const char* what, const char* of) {
    if (lua_type(L, index) != LUA_TTABLE)
        throw InputError(std::string(what) + " must be a table of " + of + ", got " + describe_value(L, index));
    return static_cast<std::size_t>(lua_rawlen(L, index));
}

/// Element `i` (1-based) of the list at `list` pushed on the stack, checked to be a table of at
/// least `min_length` values; returns its length. Pops nothing (the caller pops).
std::size_t push_element(lua_State* L, int list, std::size_t i, std::size_t min_length, const char* what,
                         const char* expected) {
    lua_rawgeti(L, list, static_cast<lua_Integer>(i));
    const std::size_t length = lua_type(L, -1) == LUA_TTABLE ? static_cast<std::size_t>(lua_rawlen(L, -1)) : 0;
    if (lua_type(L, -1) != LUA_TTABLE || length < min_length) {
        const std::string got = lua_type(L, -1) == LUA_TTABLE ? "a table of " + std::to_string(length) + " values"
                                                               : describe_value(L, -1);
        throw InputError(std::string(what) + " " + std::to_string(i) + " must be " + expected + ", got " + got);
    }
    return length;
}

/// The vertices {{x, y, z}, ...} at stack index 2: finite numbers within float range, as the OBJ
/// reader requires.
void read_inline_vertices(lua_State* L, LoaderContext& ctx, std::size_t count, MeshData& mesh) {
    for (std::size_t i = 1; i <= count; ++i) {
        check_limits(ctx, i);
        if (push_element(L, 2, i, 3, "vertex", "{x, y, z}") != 3)
            throw InputError("vertex " + std::to_string(i) + " must be {x, y, z}, got a table of " +
                             std::to_string(lua_rawlen(L, -1)) + " values");
        glm::vec3 position(0.0f);
        for (int axis = 0; axis < 3; ++axis) {
            const int type = lua_rawgeti(L, -1, axis + 1);
            const double value = lua_tonumber(L, -1);
            lua_pop(L, 1);
            const char* const names[] = {"x", "y", "z"};
            if (type != LUA_TNUMBER || !std::isfinite(value) || std::fabs(value) > FLT_MAX)
                throw InputError("vertex " + std::to_string(i) + ": " + names[axis] + " must be a finite number" +
                                 (type == LUA_TNUMBER ? " within float range, got " + format_number(value)
                                                      : std::string(", got ") + lua_typename(L, type)));
            position[axis] = static_cast<float>(value);
        }
        lua_pop(L, 1);
        mesh.positions.push_back(position);
    }
}

/// The mesh of gr.mesh's inline form (counts already checked and charged): the vertices at stack
/// index 2, the faces at 3, each face fanned around its first corner.
std::shared_ptr<MeshData> build_inline_mesh(lua_State* L, LoaderContext& ctx, std::size_t vertex_count,
                                            std::size_t triangle_count, std::size_t face_count) {
    auto mesh = std::make_shared<MeshData>();
    mesh->positions.reserve(vertex_count);
    mesh->triangles.reserve(triangle_count);
    read_inline_vertices(L, ctx, vertex_count, *mesh);
    std::vector<unsigned> corners;
    for (std::size_t f = 1; f <= face_count; ++f) {
        const std::size_t length = push_element(L, 3, f, 3, "face", "a list of at least 3 vertex indices");
        corners.clear();
        for (std::size_t k = 1; k <= length; ++k) {
            check_limits(ctx, ++ctx.library_steps);
            const int type = lua_rawgeti(L, -1, static_cast<lua_Integer>(k));
            const double value = lua_tonumber(L, -1);
            lua_pop(L, 1);
            const auto where = [&] { return "face " + std::to_string(f) + ", index " + std::to_string(k); };
            if (type != LUA_TNUMBER || value != std::floor(value))
                throw InputError(where() + " must be a whole number, got " +
                                 (type == LUA_TNUMBER ? format_number(value) : std::string(lua_typename(L, type))));
            if (!(value >= 0.0 && value < static_cast<double>(vertex_count)))
                throw InputError(where() + " is vertex " + format_number(value) + ", out of range (" +
                                 (vertex_count ? "indices are 0-based: 0.." + std::to_string(vertex_count - 1)
                                               : std::string("the vertex list is empty")) + ")");
            corners.push_back(static_cast<unsigned>(value));
        }
        lua_pop(L, 1);
        for (std::size_t k = 1; k + 1 < corners.size(); ++k)
            mesh->triangles.emplace_back(corners[0], corners[k], corners[k + 1]);
    }
    return mesh;
}

/// gr.mesh(name, {{x, y, z}, ...}, {{i, j, k, ...}, ...}): the course's inline form. Indices are
/// 0-based; every face (3 or more corners, a convex planar polygon, counter-clockwise seen from
/// outside) is fanned around its first corner, exactly as the OBJ reader fans a polygon, so the
/// mesh is the one the same vertices and faces written as an OBJ file give (without a file path).
int inline_mesh(lua_State* L, LoaderContext& ctx) {
    note_location(L, ctx);  // a stop (time limit, cancel, watchdog) while the tables are read names this line
    const std::size_t vertex_count = list_length(L, 2, "vertices", "{x, y, z}");
    const std::size_t face_count = list_length(L, 3, "faces", "index lists {i, j, k, ...}");
    if (face_count == 0) throw InputError("a mesh needs at least one face, got an empty face list");
    if (vertex_count > 0xffffffffu) throw InputError("more vertices than 32-bit indices can address");
    // Count the triangles first, so that the whole mesh is charged before any of it is made.
    std::size_t triangle_count = 0;
    for (std::size_t f = 1; f <= face_count; ++f) {
        check_limits(ctx, f);
        triangle_count += push_element(L, 3, f, 3, "face", "a list of at least 3 vertex indices") - 2;
        lua_pop(L, 1);
    }
    const std::size_t bytes = sizeof(MeshData) + vertex_count * sizeof(glm::vec3) + triangle_count * sizeof(glm::uvec3);
    charge_memory(ctx, bytes, "the mesh");
    std::shared_ptr<MeshData> mesh;
    try {
        mesh = build_inline_mesh(L, ctx, vertex_count, triangle_count, face_count);
    } catch (...) {
        release_memory(ctx, bytes);  // a script that catches the error keeps its budget
        throw;
    }
    release_memory(ctx, bytes);
    charge_memory(ctx, mesh_bytes(*mesh), "the mesh");
    return add_mesh(ctx, std::move(mesh));
}

CallResult gr_mesh(lua_State* L, LoaderContext& ctx) {
    expect_arguments(L, 1, 2, 3, "name, 'file.obj' or name, {{x,y,z}, ...}, {{i,j,k,...}, ...}");
    std::string name = string_arg(L, 1, "name");
    int mesh = -1;
    if (lua_gettop(L) == 3) {
        mesh = inline_mesh(L, ctx);
    } else {
        if (lua_type(L, 2) == LUA_TTABLE)
            throw InputError("the inline form needs vertices and faces: gr.mesh(name, {{x,y,z}, ...}, {{i,j,k,...}, ...})");
        mesh = obj_mesh(ctx, string_arg(L, 2, "file name"));
    }
    const int index = add_node(ctx, NodeKind::mesh, std::move(name), caller_location(L));
    ctx.scene.nodes[index].mesh = mesh;
    return CallResult::of(HandleKind::node, index);
}

/// The icosahedron of gr.isodecahedron: vertices (0, ±1, ±φ), (±1, ±φ, 0), (±φ, 0, ±1) with
/// φ = 1.618 (not normalised); its 20 faces are the triples of mutually adjacent vertices (edge
/// length² ≈ 4; the next distance² is 4φ² ≈ 10.5), each ordered counter-clockwise seen from outside.
std::shared_ptr<MeshData> make_isodecahedron() {
    const float phi = 1.618f;
    auto mesh = std::make_shared<MeshData>();
    for (const float a : {1.0f, -1.0f})
        for (const float b : {phi, -phi}) {
            mesh->positions.emplace_back(0.0f, a, b);
            mesh->positions.emplace_back(a, b, 0.0f);
            mesh->positions.emplace_back(b, 0.0f, a);
        }
    const auto adjacent = [&](unsigned i, unsigned j) {
        const glm::vec3 d = mesh->positions[i] - mesh->positions[j];
        return glm::dot(d, d) < 5.0f;
    };
    const unsigned count = static_cast<unsigned>(mesh->positions.size());
    for (unsigned i = 0; i < count; ++i)
        for (unsigned j = i + 1; j < count; ++j)
            for (unsigned k = j + 1; k < count; ++k) {
                if (!adjacent(i, j) || !adjacent(j, k) || !adjacent(i, k)) continue;
                const glm::vec3 &a = mesh->positions[i], &b = mesh->positions[j], &c = mesh->positions[k];
                const bool outward = glm::dot(glm::cross(b - a, c - a), a + b + c) > 0.0f;
                mesh->triangles.emplace_back(i, outward ? j : k, outward ? k : j);
            }
    return mesh;
}

CallResult gr_isodecahedron(lua_State* L, LoaderContext& ctx) {
    expect_arguments(L, 1, 1, 1, "name");
    std::string name = string_arg(L, 1, "name");
    if (ctx.isodecahedron_mesh < 0) {
        std::shared_ptr<MeshData> mesh = make_isodecahedron();
        charge_memory(ctx, mesh_bytes(*mesh), "the mesh");
        ctx.isodecahedron_mesh = add_mesh(ctx, std::move(mesh));
    }
    const int index = add_node(ctx, NodeKind::mesh, std::move(name), caller_location(L));
    ctx.scene.nodes[index].mesh = ctx.isodecahedron_mesh;
    return CallResult::of(HandleKind::node, index);
}

/// gr.union, gr.intersection, gr.difference: ([name,] a, b).
CallResult csg(lua_State* L, LoaderContext& ctx, NodeKind kind, const char* default_name) {
    const int count = lua_gettop(L);
    std::string name = default_name;
    int first = 1;
    if (count == 3) {
        name = string_arg(L, 1, "name");
        first = 2;
    } else if (count != 2) {
        throw InputError("expected 2 or 3 arguments ([name,] a, b), got " + std::to_string(count));
    }
    const int left = handle_arg(L, first, HandleKind::node, "the first operand");
    const int right = handle_arg(L, first + 1, HandleKind::node, "the second operand");
    const int index = add_node(ctx, kind, std::move(name), caller_location(L));
    ctx.scene.nodes[index].csg_left = left;
    ctx.scene.nodes[index].csg_right = right;
    ctx.node_is_held[left] = ctx.node_is_held[right] = true;
    return CallResult::of(HandleKind::node, index);
}

CallResult gr_union(lua_State* L, LoaderContext& ctx) { return csg(L, ctx, NodeKind::csg_union, "union"); }
CallResult gr_intersection(lua_State* L, LoaderContext& ctx) {
    return csg(L, ctx, NodeKind::csg_intersection, "intersection");
}
CallResult gr_difference(lua_State* L, LoaderContext& ctx) {
    return csg(L, ctx, NodeKind::csg_difference, "difference");
}

CallResult node_add_child(lua_State* L, LoaderContext& ctx) {
    const int parent = self_arg(L, HandleKind::node);
    expect_arguments(L, 2, 1, 1, "child");
    const int child = handle_arg(L, 2, HandleKind::node, "child");
    // A cycle needs the parent below the child, so held by some node: a parent nothing holds (a
    // chain built from its leaf up) is checked without walking what lies below the child.
    if (child == parent || (ctx.node_is_held[parent] && reaches(ctx, child, parent))) {
        const std::string child_name = ctx.scene.nodes[child].name, parent_name = ctx.scene.nodes[parent].name;
        throw InputError("adding '" + child_name + "' under '" + parent_name +
                         "' would make a cycle (a node cannot be its own descendant)");
    }
    charge_append(ctx, ctx.scene.nodes[parent].children, 0, "child lists");
    ctx.scene.nodes[parent].children.push_back(child);
    ctx.node_is_held[child] = true;
    return CallResult::nothing();
}

CallResult node_set_material(lua_State* L, LoaderContext& ctx) {
    const int node = self_arg(L, HandleKind::node);
    expect_arguments(L, 2, 1, 1, "material");
    ctx.scene.nodes[node].material = handle_arg(L, 2, HandleKind::material, "material");
    return CallResult::nothing();
}

/// Reads (x, y, z) after self for translate and scale.
glm::dvec3 three_numbers(lua_State* L) {
    expect_arguments(L, 2, 3, 3, "x, y, z");
    return {number_arg(L, 2, "x"), number_arg(L, 3, "y"), number_arg(L, 4, "z")};
}

void add_transform(lua_State* L, LoaderContext& ctx, int node, TransformOp op) {
    op.where = caller_location(L);
    charge_append(ctx, ctx.scene.nodes[node].transforms, op.where.file.capacity(), "recorded transforms");
    ctx.scene.nodes[node].transforms.push_back(std::move(op));
}

CallResult node_translate(lua_State* L, LoaderContext& ctx) {
    const int node = self_arg(L, HandleKind::node);
    TransformOp op;
    op.kind = TransformOp::Kind::translate;
    op.amount = three_numbers(L);
    add_transform(L, ctx, node, std::move(op));
    return CallResult::nothing();
}

CallResult node_scale(lua_State* L, LoaderContext& ctx) {
    const int node = self_arg(L, HandleKind::node);
    TransformOp op;
    op.kind = TransformOp::Kind::scale;
    op.amount = three_numbers(L);
    for (int i = 0; i < 3; ++i)
        if (op.amount[i] == 0.0)
            throw InputError("factor " + format_number(op.amount[i]) + " makes the transform singular");
    add_transform(L, ctx, node, std::move(op));
    return CallResult::nothing();
}

CallResult node_rotate(lua_State* L, LoaderContext& ctx) {
    const int node = self_arg(L, HandleKind::node);
    expect_arguments(L, 2, 2, 2, "axis, degrees");
    const char* axis_error = "axis must be 'x', 'y' or 'z'";
    if (lua_type(L, 2) != LUA_TSTRING) throw InputError(std::string(axis_error) + ", got " + describe_value(L, 2));
    const std::string axis = string_arg(L, 2, "axis");
    const char letter = axis.size() == 1 ? static_cast<char>(std::tolower(static_cast<unsigned char>(axis[0]))) : 0;
    if (letter != 'x' && letter != 'y' && letter != 'z')
        throw InputError(std::string(axis_error) + ", got '" + axis + "'");
    TransformOp op;
    op.kind = TransformOp::Kind::rotate;
    op.axis = letter - 'x';
    op.degrees = number_arg(L, 3, "degrees");
    add_transform(L, ctx, node, std::move(op));
    return CallResult::nothing();
}

const GrFunction node_function_table[] = {
    {"node", guarded<gr_node>},
    {"joint", guarded<gr_joint>},
    {"sphere", guarded<gr_sphere>},
    {"cube", guarded<gr_cube>},
    {"cylinder", guarded<gr_cylinder>},
    {"cone", guarded<gr_cone>},
    {"nh_sphere", guarded<gr_nh_sphere>},
    {"nh_box", guarded<gr_nh_box>},
    {"mesh", guarded<gr_mesh>},
    {"isodecahedron", guarded<gr_isodecahedron>},
    {"union", guarded<gr_union>},
    {"intersection", guarded<gr_intersection>},
    {"difference", guarded<gr_difference>},
};

const GrFunction node_method_table[] = {
    {"add_child", guarded<node_add_child>},
    {"set_material", guarded<node_set_material>},
    {"translate", guarded<node_translate>},
    {"scale", guarded<node_scale>},
    {"rotate", guarded<node_rotate>},
};

}  // namespace

std::span<const GrFunction> gr_node_functions() { return node_function_table; }
std::span<const GrFunction> node_methods() { return node_method_table; }

}  // namespace caustica::scene_lua
