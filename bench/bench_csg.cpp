// CSG bounding boxes: a plate drilled by a 12 x 12 grid of spheres and cylinders
// (rows of holes are groups, i.e. nested implicit unions, inside a difference), rendered at
// 256 x 256 on one thread with the boxes of CSG subtrees tested (1) and not (0).
//   build/bench_csg --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "core/scene/camera.h"
#include "core/integrators/progressive.h"
#include "core/geometry/render_scene.h"
#include "core/render/render_session.h"
#include "core/scene/scene_flatten.h"
#include "core/render/tile_renderer.h"

#include <benchmark/benchmark.h>
#include <xmmintrin.h>
#include <pmmintrin.h>

#include <memory>
#include <string>

namespace {

using namespace caustica;

constexpr int bench_size = 256;
constexpr int grid = 12;

/// Builds the scene by hand: the benchmark measures CSG, not the Lua loader.
class PlateScene {
public:
    PlateScene() {
        node(NodeKind::group, -1);  // node 0: the root
        const int plate_material = material({0.2, 0.45, 0.8}), hole_material = material({0.9, 0.7, 0.2});
        const int wall = add(0, node(NodeKind::cube, material({0.8, 0.8, 0.75})));
        op(wall, TransformOp::Kind::translate, {0, 0, -3});
        op(wall, TransformOp::Kind::scale, {8, 8, 0.1});

        const int slab = node(NodeKind::cube, plate_material);
        op(slab, TransformOp::Kind::scale, {4, 4, 0.3});
        const int holes = node(NodeKind::group, hole_material);
        for (int row = 0; row < grid; ++row) {
            const int row_group = add(holes, node(NodeKind::group, -1));
            for (int column = 0; column < grid; ++column) {
                const bool ball = (row + column) % 2 == 0;
                const int hole = add(row_group, node(ball ? NodeKind::sphere : NodeKind::cylinder, -1));
                op(hole, TransformOp::Kind::translate, {-3.3 + 0.6 * column, -3.3 + 0.6 * row, 0});
                if (ball) {
                    op(hole, TransformOp::Kind::scale, {0.24, 0.24, 0.24});
                } else {
                    rotate(hole, 0, 90);
                    op(hole, TransformOp::Kind::scale, {0.17, 0.5, 0.17});
                }
            }
        }
        const int plate = add(0, node(NodeKind::csg_difference, -1));
        scene_->nodes[plate].csg_left = slab;
        scene_->nodes[plate].csg_right = holes;
        rotate(plate, 1, 25);
        rotate(plate, 0, -20);

        job_.scene = scene_;
        job_.root = 0;
        job_.width = job_.height = bench_size;
        job_.camera = {{0.0, 0.0, 11.0}, {0.0, 0.0, -1.0}, {0.0, 1.0, 0.0}, 45.0};
        job_.ambient = {0.2, 0.2, 0.2};
        LightDesc light;
        light.position = {5, 6, 9};
        light.colour = {1, 1, 1};
        scene_->lights.push_back(light);
        job_.lights = {0};
    }

    const RenderJob& job() const { return job_; }

private:
    int material(glm::dvec3 kd) {
        MaterialDesc m;
        m.kd = kd;
        scene_->materials.push_back(m);
        return static_cast<int>(scene_->materials.size()) - 1;
    }
    int node(NodeKind kind, int material) {
        NodeDesc n;
        n.kind = kind;
        n.material = material;
        n.name = "node" + std::to_string(scene_->nodes.size());
        scene_->nodes.push_back(n);
        return static_cast<int>(scene_->nodes.size()) - 1;
    }
    int add(int parent, int child) {
        scene_->nodes[parent].children.push_back(child);
        return child;
    }
    void op(int index, TransformOp::Kind kind, glm::dvec3 amount) {
        TransformOp t;
        t.kind = kind;
        t.amount = amount;
        scene_->nodes[index].transforms.push_back(t);
    }
    void rotate(int index, int axis, double degrees) {
        TransformOp t;
        t.kind = TransformOp::Kind::rotate;
        t.axis = axis;
        t.degrees = degrees;
        scene_->nodes[index].transforms.push_back(t);
    }

    std::shared_ptr<SceneDesc> scene_ = std::make_shared<SceneDesc>();
    RenderJob job_;
};

/// One Phong-shaded sample per pixel (with shadow rays) of the drilled plate, one thread.
void BM_CsgPlate(benchmark::State& state) {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    const PlateScene plate;
    const RenderJob& job = plate.job();
    FlatScene flat = flatten_scene(job);
    flat.csg_bounding_boxes = state.range(0) != 0;
    const RenderScene scene(*job.scene, flat);
    ShadingSetup setup;
    setup.scene = &scene;
    for (int index : job.lights) {
        const LightDesc& d = job.scene->lights[index];
        setup.lights.push_back({glm::vec3(d.position), glm::vec3(d.colour), glm::vec3(d.falloff), 0.0f});
    }
    setup.ambient = glm::vec3(job.ambient);
    const ProgressiveIntegrator integrator(setup);
    const Camera camera(job.camera, job.width, job.height);
    TileContext context;
    context.integrator = &integrator;
    context.camera = &camera;
    const std::vector<Tile> tiles = make_tiles(job.width, job.height, tile_size);
    Image image(job.width, job.height);
    RayCounters counters;
    for (auto _ : state) {
        for (const Tile& tile : tiles) render_first_pass_tile(context, tile, image, counters);
        benchmark::DoNotOptimize(image.pixels.data());
    }
    state.SetItemsProcessed(state.iterations() * job.width * job.height);
    state.counters["csg_leaves"] = double(scene.info().csg_leaves);
}

BENCHMARK(BM_CsgPlate)->ArgName("csg_bb")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
