#include "core/render/fingerprints.h"

#include "core/io/png_io.h"
#include "core/render/random.h"
#include "core/scene/options.h"

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace caustica {
namespace {

std::uint64_t hash_vec(std::uint64_t h, const glm::dvec3& v) {
    return hash_double(hash_double(hash_double(h, v.x), v.y), v.z);
}

/// Folds an index that may be -1 (none) into a running hash, in unsigned arithmetic.
std::uint64_t hash_index(std::uint64_t h, int index) {
    return hash_combine(h, static_cast<std::uint64_t>(static_cast<std::int64_t>(index) + 1));
}

/// What the BVH and materials depend on; meshes by address (a cache key within this process) or,
/// `by_content`, by their vertices (the same in every process that loaded the same files).
std::uint64_t hash_geometry(const RenderJob& job, bool by_content) {
    std::uint64_t h = hash_combine(0x6361757374696361ULL, static_cast<std::uint64_t>(job.root));
    h = hash_options_feeding(h, job.options, stage_scene);
    const SceneDesc& scene = *job.scene;
    for (const NodeDesc& node : scene.nodes) {
        h = hash_combine(h, static_cast<std::uint64_t>(node.kind));
        for (const TransformOp& op : node.transforms) {
            h = hash_combine(h, static_cast<std::uint64_t>(op.kind) * 4 + static_cast<std::uint64_t>(op.axis));
            h = hash_double(hash_vec(h, op.amount), op.degrees);
        }
        for (int child : node.children) h = hash_index(h, child);
        h = hash_index(h, node.material);
        h = hash_double(hash_vec(h, node.position), node.size);
        h = hash_index(h, node.mesh);
        h = hash_index(hash_index(h, node.csg_left), node.csg_right);
    }
    for (const MaterialDesc& m : scene.materials) {
        h = hash_double(hash_vec(hash_vec(h, m.kd), m.ks), m.shininess);
        h = hash_combine(h, (m.reflective ? 1 : 0) + (m.air ? 2 : 0) + (m.refractive_index ? 4 : 0));
        h = hash_double(h, m.refractive_index.value_or(0.0));
        h = hash_index(hash_index(h, m.texture), m.bumpmap);
    }
    for (const TextureDesc& t : scene.textures) {
        h = hash_combine(h, std::hash<std::string>{}(t.source));
        h = hash_combine(h, std::hash<std::string>{}(t.remap) + (t.procedural ? 1 : 0));
        if (by_content && t.image) {  // the decoded pixels: a file edited under the same name differs
            const Png8& png = *t.image;
            h = hash_combine(h, (std::uint64_t(png.width) << 40) ^ (std::uint64_t(png.height) << 8) ^ png.channels);
            h = hash_combine(h, std::hash<std::string_view>{}(std::string_view(
                                    reinterpret_cast<const char*>(png.data.data()), png.data.size())));
        }
    }
    for (const auto& mesh : scene.meshes) {
        if (!by_content || !mesh) {
            h = hash_combine(h, reinterpret_cast<std::uintptr_t>(mesh.get()));
            continue;
        }
        h = hash_combine(h, mesh->positions.size() * 31 + mesh->triangles.size());
        for (const glm::vec3& p : mesh->positions) h = hash_double(hash_double(hash_double(h, p.x), p.y), p.z);
        for (const glm::uvec3& t : mesh->triangles)
            h = hash_combine(h, (std::uint64_t(t.x) << 42) ^ (std::uint64_t(t.y) << 21) ^ t.z);
        for (const glm::vec2& uv : mesh->texcoords) h = hash_double(hash_double(h, uv.x), uv.y);
    }
    return h;
}

/// The lights, ambient light and background of a job.
std::uint64_t hash_lighting(std::uint64_t h, const RenderJob& job) {
    h = hash_vec(hash_vec(h, job.ambient), job.miss_colour);
    for (int l : job.lights) {
        const LightDesc& light = job.scene->lights.at(static_cast<std::size_t>(l));
        h = hash_double(hash_vec(hash_vec(hash_vec(h, light.position), light.colour), light.falloff), light.radius);
    }
    return h;
}

}  // namespace

std::uint64_t scene_content_fingerprint(const RenderJob& job) { return hash_lighting(hash_geometry(job, true), job); }

std::uint64_t geometry_fingerprint(const RenderJob& job) { return hash_geometry(job, false); }

std::uint64_t job_content_fingerprint(const RenderJob& job) {
    std::uint64_t h = hash_geometry(job, true);
    h = hash_options_feeding(h, job.options, stage_scene | stage_photons | stage_image | stage_output);
    h = hash_vec(hash_vec(hash_vec(h, job.camera.eye), job.camera.view), job.camera.up);
    h = hash_double(h, job.camera.fovy_degrees);
    h = hash_combine(hash_combine(h, static_cast<std::uint64_t>(job.width)), static_cast<std::uint64_t>(job.height));
    return hash_lighting(h, job);
}

}  // namespace caustica
