// Helpers for tests that build scenes in C++ rather than Lua.
#pragma once

#include "core/scene/camera.h"
#include "core/render/render_session.h"
#include "core/scene/scene_desc.h"

#include <cmath>
#include <memory>
#include <vector>

namespace caustica::testing {

/// Builds a SceneDesc and a RenderJob by hand.
struct JobBuilder {
    std::shared_ptr<SceneDesc> scene = std::make_shared<SceneDesc>();
    RenderJob job;

    JobBuilder(int width, int height) {
        job.width = width;
        job.height = height;
        job.output = "test.png";
        scene->nodes.push_back(NodeDesc{});  // node 0: the root group
        scene->nodes[0].name = "root";
        job.root = 0;
        job.options.reproducible = true;
        job.options.silent = true;
    }

    int material(glm::dvec3 kd, glm::dvec3 ks = glm::dvec3(0.0), double shininess = 0.0, bool reflective = false) {
        MaterialDesc m;
        m.kd = kd;
        m.ks = ks;
        m.shininess = shininess;
        m.reflective = reflective;
        scene->materials.push_back(m);
        return static_cast<int>(scene->materials.size()) - 1;
    }

    /// Adds a primitive node under `parent` (root by default) and returns its index.
    int add(NodeKind kind, int material, int parent = 0) {
        NodeDesc n;
        n.kind = kind;
        n.name = "node" + std::to_string(scene->nodes.size());
        n.material = material;
        scene->nodes.push_back(n);
        const int index = static_cast<int>(scene->nodes.size()) - 1;
        scene->nodes[parent].children.push_back(index);
        return index;
    }

    void translate(int node, glm::dvec3 v) { push_op(node, TransformOp::Kind::translate, v); }
    void scale(int node, glm::dvec3 v) { push_op(node, TransformOp::Kind::scale, v); }
    void rotate(int node, int axis, double degrees) {
        TransformOp op;
        op.kind = TransformOp::Kind::rotate;
        op.axis = axis;
        op.degrees = degrees;
        scene->nodes[node].transforms.push_back(op);
    }

    void light(glm::dvec3 position, glm::dvec3 colour, glm::dvec3 falloff = {1.0, 0.0, 0.0}) {
        LightDesc l;
        l.position = position;
        l.colour = colour;
        l.falloff = falloff;
        scene->lights.push_back(l);
        job.lights.push_back(static_cast<int>(scene->lights.size()) - 1);
    }

    void camera(glm::dvec3 eye, glm::dvec3 view, double fovy = 50.0, glm::dvec3 up = {0.0, 1.0, 0.0}) {
        job.camera = {eye, view, up, fovy};
    }

    RenderJob build() {
        RenderJob j = job;
        j.scene = scene;
        return j;
    }

private:
    void push_op(int node, TransformOp::Kind kind, glm::dvec3 v) {
        TransformOp op;
        op.kind = kind;
        op.amount = v;
        scene->nodes[node].transforms.push_back(op);
    }
};

/// The virtual-light scene: a diffuse ceiling lit only through a large mirror below a point
/// light, whose direct light is stopped by a small black blocker just above it.
/// With `mirrored_light`, the mirror is gone and a light of intensity ks I sits at the mirror image.
inline JobBuilder virtual_light_scene(bool mirrored_light, double scale = 1.0) {
    JobBuilder b(48, 48);
    const int root = b.add(NodeKind::group, -1);
    b.scale(root, glm::dvec3(scale));
    const int ceiling = b.add(NodeKind::cube, b.material({0.8, 0.8, 0.8}), root);
    b.translate(ceiling, {0, 3, 0});
    b.scale(ceiling, {2, 0.05, 2});
    const int blocker = b.add(NodeKind::cube, b.material({0, 0, 0}), root);
    b.translate(blocker, {0, 1.1, 0});
    b.scale(blocker, {0.15, 0.005, 0.15});
    const double ks = 0.9;
    if (!mirrored_light) {
        const int mirror = b.add(NodeKind::cube, b.material({0, 0, 0}, glm::dvec3(ks), 0, true), root);
        b.translate(mirror, {0, -0.025, 0});
        b.scale(mirror, {3, 0.025, 3});
        b.light(glm::dvec3(0, 1, 0) * scale, {1, 1, 1}, {0, 0, 1});
    } else {
        b.light(glm::dvec3(0, -1, 0) * scale, glm::dvec3(ks), {0, 0, 1.0});
    }
    b.camera(glm::dvec3(0, 0.5, 0) * scale, {0, 1, 0}, 90, {0, 0, -1});
    b.job.options.disable_aa = true;
    b.job.options.unit_distance = scale;
    return b;
}

/// Pixels of a virtual_light_scene image that see the ceiling between radii 0.5 and 1.8 around
/// its centre: lit only through the mirror, outside the blocker's shadow.
inline std::vector<std::size_t> virtual_light_annulus(const RenderJob& job, double scale = 1.0) {
    const Camera camera(job.camera, job.width, job.height);
    std::vector<std::size_t> pixels;
    for (int y = 0; y < job.height; ++y)
        for (int x = 0; x < job.width; ++x) {
            const Ray ray = camera.generate(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
            const float t = (2.95f * static_cast<float>(scale) - ray.origin.y) / ray.direction.y;
            const glm::vec3 p = (ray.origin + t * ray.direction) / static_cast<float>(scale);
            const float r = std::sqrt(p.x * p.x + p.z * p.z);
            if (r >= 0.5f && r <= 1.8f) pixels.push_back(static_cast<std::size_t>(y) * job.width + x);
        }
    return pixels;
}

/// Renders a job to completion and returns the image.
inline Image render(const RenderJob& job) {
    RenderSession session;
    session.set_job(job);
    session.start();
    session.wait();
    return session.image();
}

}  // namespace caustica::testing
