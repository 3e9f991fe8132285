// Helpers for tests that build scenes in C++ rather than Lua.
#pragma once

#include "core/render_session.h"
#include "core/scene_desc.h"

#include <memory>

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

/// Renders a job to completion and returns the image.
inline Image render(const RenderJob& job) {
    RenderSession session;
    session.set_job(job);
    session.start();
    session.wait();
    return session.image();
}

}  // namespace caustica::testing
