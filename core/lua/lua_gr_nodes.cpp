// The node half of the gr API: primitives, meshes, CSG, hierarchy and transforms.
// Transforms are recorded in call order; the renderer composes them under the convention in force.
#include "core/lua/lua_context.h"
#include "core/lua/scene_files.h"
#include "core/geometry/mesh_obj.h"

#include <cctype>

namespace caustica::scene_lua {
namespace {

int add_node(LoaderContext& ctx, NodeKind kind, std::string name, SourceLocation where) {
    charge_append(ctx, ctx.scene.nodes, name.capacity() + where.file.capacity(), "scene nodes");
    NodeDesc node;
    node.name = std::move(name);
    node.kind = kind;
    node.where = std::move(where);
    ctx.scene.nodes.push_back(std::move(node));
    return static_cast<int>(ctx.scene.nodes.size()) - 1;
}

/// True when `target` is `from` or below it (children and CSG operands).
bool reaches(const SceneDesc& scene, int from, int target) {
    std::vector<char> seen(scene.nodes.size(), 0);
    std::vector<int> stack{from};
    while (!stack.empty()) {
        const int index = stack.back();
        stack.pop_back();
        if (index == target) return true;
        if (index < 0 || seen[index]) continue;
        seen[index] = 1;
        const NodeDesc& node = scene.nodes[index];
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

CallResult gr_mesh(lua_State* L, LoaderContext& ctx) {
    expect_arguments(L, 1, 2, 2, "name, 'file.obj'");
    std::string name = string_arg(L, 1, "name");
    const std::string as_written = string_arg(L, 2, "file name");
    const SceneFile file = open_scene_file(ctx, as_written);
    int mesh = -1;
    const std::pair<std::uint64_t, std::uint64_t> identity{file.device, file.inode};
    if (auto cached = ctx.mesh_cache.find(identity); cached != ctx.mesh_cache.end()) {
        mesh = cached->second;
    } else {
        std::shared_ptr<const MeshData> data;
        {
            const std::string text = read_scene_file(ctx, file, "the mesh file");
            data = parse_obj_mesh(text, as_written, file.path);
            release_memory(ctx, text.size());  // the text goes; the mesh is charged instead
        }
        charge_memory(ctx, mesh_bytes(*data), "the mesh");
        ctx.scene.meshes.push_back(std::move(data));
        mesh = static_cast<int>(ctx.scene.meshes.size()) - 1;
        ctx.mesh_cache.emplace(identity, mesh);
    }
    const int index = add_node(ctx, NodeKind::mesh, std::move(name), caller_location(L));
    ctx.scene.nodes[index].mesh = mesh;
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
    if (reaches(ctx.scene, child, parent)) {
        const std::string child_name = ctx.scene.nodes[child].name, parent_name = ctx.scene.nodes[parent].name;
        throw InputError("adding '" + child_name + "' under '" + parent_name +
                         "' would make a cycle (a node cannot be its own descendant)");
    }
    charge_append(ctx, ctx.scene.nodes[parent].children, 0, "child lists");
    ctx.scene.nodes[parent].children.push_back(child);
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
