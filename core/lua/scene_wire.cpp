#include "core/lua/scene_wire.h"

#include "core/io/png_io.h"
#include "core/util/printable_text.h"

#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <type_traits>

namespace caustica::scene_lua {
namespace {

constexpr std::uint32_t wire_magic = 0x43535331u;  // "CSS1"

static_assert(std::is_trivially_copyable_v<Options>, "Options travels as raw bytes: keep it plain data");

/// Appends values to a byte string.
class Writer {
public:
    template <class T>
    void pod(const T& value) {
        static_assert(std::is_trivially_copyable_v<T>);
        out_.append(reinterpret_cast<const char*>(&value), sizeof value);
    }
    void size(std::size_t n) { pod(static_cast<std::uint64_t>(n)); }
    void text(const std::string& s) {
        size(s.size());
        out_.append(s);
    }
    template <class T>
    void pods(const std::vector<T>& values) {
        static_assert(std::is_trivially_copyable_v<T>);
        size(values.size());
        out_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
    }
    void where(const SourceLocation& location) {
        text(location.file);
        pod(location.line);
    }
    std::string take() { return std::move(out_); }

private:
    std::string out_;
};

/// Reads values back, refusing to read past the end.
class Reader {
public:
    explicit Reader(std::string_view bytes) : bytes_(bytes) {}

    template <class T>
    T pod() {
        static_assert(std::is_trivially_copyable_v<T>);
        T value;
        std::memcpy(&value, take(sizeof value), sizeof value);
        return value;
    }
    /// A count of items of `item_bytes` each, checked against the bytes left.
    std::size_t size(std::size_t item_bytes = 1) {
        const auto n = pod<std::uint64_t>();
        if (item_bytes != 0 && n > (bytes_.size() - at_) / item_bytes) fail();
        return static_cast<std::size_t>(n);
    }
    std::string text() { return std::string(text_view()); }
    /// A text where it lies in the bytes (no copy).
    std::string_view text_view() {
        const std::size_t n = size();
        return std::string_view(take(n), n);
    }
    template <class T>
    std::vector<T> pods() {
        const std::size_t n = size(sizeof(T));
        std::vector<T> values(n);
        if (n) std::memcpy(values.data(), take(n * sizeof(T)), n * sizeof(T));
        return values;
    }
    SourceLocation where() {
        SourceLocation location;
        location.file = text();
        location.line = pod<int>();
        return location;
    }
    /// An index into a table of `count` entries, or -1.
    int index(std::size_t count) {
        const auto i = pod<std::int64_t>();
        if (i < -1 || i >= static_cast<std::int64_t>(count)) fail();
        return static_cast<int>(i);
    }
    bool flag() { return pod<std::uint8_t>() != 0; }
    bool done() const { return at_ == bytes_.size(); }
    [[noreturn]] static void fail() { throw std::runtime_error("the scene loader's answer is damaged"); }

private:
    const char* take(std::size_t n) {
        if (n > bytes_.size() - at_) fail();
        const char* p = bytes_.data() + at_;
        at_ += n;
        return p;
    }
    std::string_view bytes_;
    std::size_t at_ = 0;
};

/// Numbers shared objects in order of first appearance.
template <class T>
class Table {
public:
    std::int64_t add(const T* object) {
        if (!object) return -1;
        auto [it, inserted] = index_.emplace(object, static_cast<std::int64_t>(order_.size()));
        if (inserted) order_.push_back(object);
        return it->second;
    }
    const std::vector<const T*>& order() const { return order_; }

private:
    std::map<const T*, std::int64_t> index_;
    std::vector<const T*> order_;
};

void write_node(Writer& w, const NodeDesc& node) {
    w.text(node.name);
    w.pod(node.kind);
    w.where(node.where);
    w.size(node.transforms.size());
    for (const TransformOp& op : node.transforms) {
        w.pod(op.kind);
        w.pod(op.amount);
        w.pod(op.axis);
        w.pod(op.degrees);
        w.where(op.where);
    }
    w.pods(node.children);
    w.pod(node.material);
    w.pod(node.position);
    w.pod(node.size);
    w.pod(node.mesh);
    w.pod(node.csg_left);
    w.pod(node.csg_right);
}

NodeDesc read_node(Reader& r) {
    NodeDesc node;
    node.name = r.text();
    node.kind = r.pod<NodeKind>();
    node.where = r.where();
    node.transforms.resize(r.size(sizeof(TransformOp::Kind)));
    for (TransformOp& op : node.transforms) {
        op.kind = r.pod<TransformOp::Kind>();
        op.amount = r.pod<glm::dvec3>();
        op.axis = r.pod<int>();
        op.degrees = r.pod<double>();
        op.where = r.where();
    }
    node.children = r.pods<int>();
    node.material = r.pod<int>();
    node.position = r.pod<glm::dvec3>();
    node.size = r.pod<double>();
    node.mesh = r.pod<int>();
    node.csg_left = r.pod<int>();
    node.csg_right = r.pod<int>();
    return node;
}

void write_scene(Writer& w, const SceneDesc& scene, Table<MeshData>& meshes, Table<Png8>& images) {
    w.size(scene.nodes.size());
    for (const NodeDesc& node : scene.nodes) write_node(w, node);
    w.size(scene.materials.size());
    for (const MaterialDesc& m : scene.materials) {
        w.pod(m.kd);
        w.pod(m.ks);
        w.pod(m.shininess);
        w.pod(static_cast<std::uint8_t>(m.reflective));
        w.pod(static_cast<std::uint8_t>(m.refractive_index.has_value()));
        w.pod(m.refractive_index.value_or(0.0));
        w.pod(static_cast<std::uint8_t>(m.air));
        w.pod(m.texture);
        w.pod(m.bumpmap);
        w.where(m.where);
    }
    w.size(scene.lights.size());
    for (const LightDesc& light : scene.lights) {
        w.pod(light.position);
        w.pod(light.colour);
        w.pod(light.falloff);
        w.pod(light.radius);
        w.where(light.where);
    }
    w.size(scene.textures.size());
    for (const TextureDesc& t : scene.textures) {
        w.text(t.source);
        w.pod(static_cast<std::uint8_t>(t.procedural));
        w.text(t.remap);
        w.pod(images.add(t.image.get()));
        w.where(t.where);
    }
    w.size(scene.meshes.size());
    for (const auto& mesh : scene.meshes) w.pod(meshes.add(mesh.get()));
}

bool in_range(int index, std::size_t count, bool none_allowed) {
    return (none_allowed && index == -1) || (index >= 0 && static_cast<std::size_t>(index) < count);
}

/// Every index in the scene points at an entry that exists (the renderer relies on it).
void check_indices(const SceneDesc& scene) {
    const std::size_t nodes = scene.nodes.size();
    for (const NodeDesc& node : scene.nodes) {
        if (node.kind < NodeKind::group || node.kind > NodeKind::csg_difference) Reader::fail();
        for (int child : node.children)
            if (!in_range(child, nodes, false)) Reader::fail();
        for (const TransformOp& op : node.transforms)
            if (op.kind < TransformOp::Kind::translate || op.kind > TransformOp::Kind::rotate || op.axis < 0 || op.axis > 2)
                Reader::fail();
        if (!in_range(node.material, scene.materials.size(), true) || !in_range(node.mesh, scene.meshes.size(), true) ||
            !in_range(node.csg_left, nodes, true) || !in_range(node.csg_right, nodes, true))
            Reader::fail();
    }
    // No cycles through children or operands (the loader refuses them; flattening assumes it).
    std::vector<std::uint8_t> state(nodes, 0);  // 0 new, 1 on the path, 2 done
    std::vector<std::pair<int, std::size_t>> path;
    for (std::size_t start = 0; start < nodes; ++start) {
        if (state[start]) continue;
        path.push_back({static_cast<int>(start), 0});
        state[start] = 1;
        while (!path.empty()) {
            auto& [node, next] = path.back();
            const NodeDesc& desc = scene.nodes[node];
            const std::size_t edges = desc.children.size() + 2;
            if (next == edges) {
                state[node] = 2;
                path.pop_back();
                continue;
            }
            const std::size_t edge = next++;
            const int to = edge < desc.children.size() ? desc.children[edge]
                           : edge == desc.children.size() ? desc.csg_left : desc.csg_right;
            if (to < 0 || state[to] == 2) continue;
            if (state[to] == 1) Reader::fail();
            state[to] = 1;
            path.push_back({to, 0});
        }
    }
    for (const MaterialDesc& m : scene.materials)
        if (!in_range(m.texture, scene.textures.size(), true) || !in_range(m.bumpmap, scene.textures.size(), true))
            Reader::fail();
}

SceneDesc read_scene(Reader& r, const std::vector<std::shared_ptr<const MeshData>>& meshes,
                     const std::vector<std::shared_ptr<const Png8>>& images) {
    SceneDesc scene;
    scene.nodes.resize(r.size(8));
    for (NodeDesc& node : scene.nodes) node = read_node(r);
    scene.materials.resize(r.size(8));
    for (MaterialDesc& m : scene.materials) {
        m.kd = r.pod<glm::dvec3>();
        m.ks = r.pod<glm::dvec3>();
        m.shininess = r.pod<double>();
        m.reflective = r.flag();
        const bool refractive = r.flag();
        const double index = r.pod<double>();
        if (refractive) m.refractive_index = index;
        m.air = r.flag();
        m.texture = r.pod<int>();
        m.bumpmap = r.pod<int>();
        m.where = r.where();
    }
    scene.lights.resize(r.size(8));
    for (LightDesc& light : scene.lights) {
        light.position = r.pod<glm::dvec3>();
        light.colour = r.pod<glm::dvec3>();
        light.falloff = r.pod<glm::dvec3>();
        light.radius = r.pod<double>();
        light.where = r.where();
    }
    scene.textures.resize(r.size(8));
    for (TextureDesc& t : scene.textures) {
        t.source = r.text();
        t.procedural = r.flag();
        t.remap = r.text();
        const int image = r.index(images.size());
        if (image >= 0) t.image = images[image];
        t.where = r.where();
    }
    scene.meshes.resize(r.size(8));
    for (auto& mesh : scene.meshes) {
        const int index = r.index(meshes.size());
        if (index < 0) Reader::fail();
        mesh = meshes[index];
    }
    check_indices(scene);
    return scene;
}

}  // namespace

std::string encode_scene_script(const SceneScript& script) {
    Table<SceneDesc> scenes;
    Table<MeshData> meshes;
    Table<Png8> images;
    for (const RenderJob& job : script.renders) scenes.add(job.scene.get());
    Writer scene_bytes;  // written first: it numbers the meshes and images
    for (const SceneDesc* scene : scenes.order()) write_scene(scene_bytes, *scene, meshes, images);

    Writer w;
    w.pod(wire_magic);
    w.text(script.path);
    w.size(script.warnings.size());
    for (const std::string& warning : script.warnings) w.text(warning);
    w.size(images.order().size());
    for (const Png8* image : images.order()) {
        w.pod(image->width);
        w.pod(image->height);
        w.pod(image->channels);
        w.pods(image->data);
    }
    w.size(meshes.order().size());
    for (const MeshData* mesh : meshes.order()) {
        w.text(mesh->path);
        w.pods(mesh->positions);
        w.pods(mesh->triangles);
        w.pods(mesh->texcoords);
    }
    w.size(scenes.order().size());
    std::string out = w.take();
    out += scene_bytes.take();
    Writer jobs;
    jobs.size(script.renders.size());
    for (const RenderJob& job : script.renders) {
        jobs.pod(scenes.add(job.scene.get()));
        jobs.pod(job.root);
        jobs.text(job.output);
        jobs.pod(job.width);
        jobs.pod(job.height);
        jobs.pod(job.camera);
        jobs.pod(job.ambient);
        jobs.pods(job.lights);
        jobs.pod(job.miss_colour);
        jobs.pod(job.options);
        jobs.where(job.where);
        jobs.size(job.option_origins.size());
        for (const auto& [name, where] : job.option_origins) {
            jobs.text(name);
            jobs.where(where);
        }
    }
    out += jobs.take();
    return out;
}

SceneScript decode_scene_script(std::string_view bytes) {
    Reader r(bytes);
    if (r.pod<std::uint32_t>() != wire_magic) Reader::fail();
    SceneScript script;
    script.path = r.text();
    // The loader bounded its warnings and made them printable; they are bounded again here, so
    // that no other sender can make the renderer show (or hold a copy of) more
    // (docs/RELIABILITY.md, "Script text reaches the user bounded and visible"). Twice the
    // loader's own total leaves room for its closing line: what it sent passes unchanged.
    ScriptOutputBudget shown_warnings(2 * script_output_limit, printable_text_max_bytes(shown_message_limit));
    for (std::size_t count = r.size(8), i = 0; i < count; ++i)
        if (std::optional<std::string> warning = shown_warnings.admit(r.text_view()))
            script.warnings.push_back(std::move(*warning));
    if (const std::string more = shown_warnings.summary("warnings"); !more.empty())
        script.warnings.push_back(printable_text(script.path) + ": " + more);
    std::vector<std::shared_ptr<const Png8>> images(r.size(8));
    for (auto& image : images) {
        Png8 png;
        png.width = r.pod<int>();
        png.height = r.pod<int>();
        png.channels = r.pod<int>();
        png.data = r.pods<unsigned char>();
        if (png.width <= 0 || png.height <= 0 || png.channels <= 0 ||
            png.data.size() != static_cast<std::size_t>(png.width) * png.height * png.channels)
            Reader::fail();
        image = std::make_shared<const Png8>(std::move(png));
    }
    std::vector<std::shared_ptr<const MeshData>> meshes(r.size(8));
    for (auto& mesh : meshes) {
        auto data = std::make_shared<MeshData>();
        data->path = r.text();
        data->positions = r.pods<glm::vec3>();
        data->triangles = r.pods<glm::uvec3>();
        data->texcoords = r.pods<glm::vec2>();
        for (const glm::uvec3& t : data->triangles)
            if (t.x >= data->positions.size() || t.y >= data->positions.size() || t.z >= data->positions.size())
                Reader::fail();
        mesh = std::move(data);
    }
    std::vector<std::shared_ptr<const SceneDesc>> scenes(r.size(8));
    for (auto& scene : scenes) scene = std::make_shared<const SceneDesc>(read_scene(r, meshes, images));
    script.renders.resize(r.size(8));
    for (RenderJob& job : script.renders) {
        const int scene = r.index(scenes.size());
        if (scene < 0) Reader::fail();
        job.scene = scenes[scene];
        job.root = r.pod<int>();
        job.output = r.text();
        job.width = r.pod<int>();
        job.height = r.pod<int>();
        job.camera = r.pod<CameraDesc>();
        job.ambient = r.pod<glm::dvec3>();
        job.lights = r.pods<int>();
        job.miss_colour = r.pod<glm::dvec3>();
        job.options = r.pod<Options>();
        job.where = r.where();
        job.option_origins.resize(r.size(8));
        for (auto& [name, where] : job.option_origins) {
            name = r.text();
            where = r.where();
        }
        if (!in_range(job.root, job.scene->nodes.size(), false)) Reader::fail();
        for (int light : job.lights)
            if (!in_range(light, job.scene->lights.size(), false)) Reader::fail();
    }
    if (!r.done()) Reader::fail();
    return script;
}

}  // namespace caustica::scene_lua
