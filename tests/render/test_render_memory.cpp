// The renderer's memory budget (docs/RELIABILITY.md, "Bounded memory"): what a job will cost once
// built is its formula (a mesh once whatever its instances, the photon maps known before the
// build), a job over --render-memory is refused before anything is built, naming the call that
// made the largest part, and the same job under a larger budget renders.
#include "core/geometry/render_scene.h"
#include "core/geometry/scene_memory.h"
#include "core/photons/photon_tracer.h"
#include "core/render/render_memory.h"
#include "core/render/render_session.h"
#include "core/scene/scene_flatten.h"
#include "core/scene/source_location.h"
#include "tests/scene_test_helpers.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

using namespace caustica;

namespace {

/// A strip of `triangles` separate triangles made in Lua (3 vertices each), its gr.mesh on line 8,
/// placed twice (two nodes share the one mesh), rendered at 16 x 16 by the gr.render of line 13.
std::string strip_scene(int triangles) {
    return "local verts, faces = {}, {}\n"
           "for i = 0, " + std::to_string(triangles - 1) + " do\n"
           "  verts[#verts + 1] = {i / 1000, 0, 0}\n"
           "  verts[#verts + 1] = {i / 1000, 1, 0}\n"
           "  verts[#verts + 1] = {i / 1000 + 0.001, 0, 0}\n"
           "  faces[#faces + 1] = {3 * i, 3 * i + 1, 3 * i + 2}\n"
           "end\n"
           "local strip = gr.mesh('strip', verts, faces)\n"
           "strip:set_material(gr.material({0.8, 0.8, 0.8}, {0, 0, 0}, 10))\n"
           "local left = gr.node('left') left:add_child(strip) left:translate(-2, 0, 0)\n"
           "local right = gr.node('right') right:add_child(strip) right:translate(2, 0, 0)\n"
           "local root = gr.node('root') root:add_child(left) root:add_child(right)\n"
           "gr.render(root, 'strip.png', 16, 16, {0, 0, 20}, {0, 0, -1}, {0, 1, 0}, 50, {0.1, 0.1, 0.1},"
           " {gr.light({0, 5, 5}, {1, 1, 1}, {1, 0, 0})})\n";
}

/// A glass ball under two lights with a quadratic falloff (lines 6 and 7) and one without (line 8),
/// with --gi and 100 000 GI photons set on line 1; its gr.render is on line 9.
const char* ball_scene = "gr.option('--gi --gi-num-photons 100000')\n"
                         "local glass = gr.material({0, 0, 0}, {0.9, 0.9, 0.9}, 20)\n"
                         "glass:set_ri(1.5)\n"
                         "local ball = gr.nh_sphere('ball', {0, 1, 0}, 0.5)\n"
                         "ball:set_material(glass)\n"
                         "local lit = gr.light({0, 4, 0}, {1, 1, 1}, {1, 0, 0.1})\n"
                         "local also_lit = gr.light({1, 4, 0}, {1, 1, 1}, {0, 0, 1})\n"
                         "local unlit = gr.light({2, 4, 0}, {1, 1, 1}, {1, 0, 0})\n"
                         "gr.render(ball, 'ball.png', 8, 8, {0, 0, 5}, {0, 0, -1}, {0, 1, 0}, 50, {0, 0, 0},"
                         " {lit, also_lit, unlit})\n";

/// The charges whose description starts with `prefix`.
std::vector<MemoryCharge> charges_about(const std::vector<MemoryCharge>& charges, const std::string& prefix) {
    std::vector<MemoryCharge> found;
    for (const MemoryCharge& c : charges)
        if (c.what.rfind(prefix, 0) == 0) found.push_back(c);
    return found;
}

/// Expects one charge about `prefix`, of `bytes` bytes, made by `call` on `line`.
void expect_one_charge(const std::vector<MemoryCharge>& charges, const std::string& prefix, double bytes,
                       const std::string& call, int line) {
    const std::vector<MemoryCharge> found = charges_about(charges, prefix);
    ASSERT_EQ(found.size(), 1u) << prefix;
    EXPECT_DOUBLE_EQ(found[0].bytes, bytes) << prefix;
    EXPECT_EQ(found[0].call, call) << prefix;
    EXPECT_EQ(found[0].where.line, line) << prefix;
}

std::string mebibytes(double bytes) {
    char text[64];
    std::snprintf(text, sizeof text, "%.1f MiB", bytes / 1048576.0);
    return text;
}

/// What the strip of `triangles` triangles costs once built, by the formula of scene_memory.h:
/// per triangle our indices and Embree's copy (12 + 12), a PrimRef (32), a Triangle4 leaf share
/// with Embree's 1.2 margin (1.2 x 176 / 4) and a BVH8 node share (256 / 32); per vertex our
/// position and Embree's copy (12 + 12).
double strip_mesh_bytes(int triangles) {
    return triangles * (12.0 + 12.0 + 32.0 + 1.2 * 176.0 / 4.0 + 256.0 / 32.0) + 3.0 * triangles * (12.0 + 12.0);
}

/// The error session.prepare() refuses the job with, or "(no error)".
std::string prepare_error(RenderSession& session) {
    try {
        session.prepare();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no error)";
}

}  // namespace

TEST(RenderMemory, AMeshIsChargedOnceByItsFormulaWhateverItsInstances) {
    const RenderJob job = caustica::testing::load_first_job(strip_scene(1000));
    const FlatScene flat = flatten_scene(job);
    const std::vector<MemoryCharge> charges = render_memory_charges(job, flat);
    // One BVH for the mesh, instanced twice.
    expect_one_charge(charges, "the mesh (1000 triangles, 3000 vertices)", strip_mesh_bytes(1000), "gr.mesh", 8);
    const double mesh_bytes = charges_about(charges, "the mesh").at(0).bytes;
    // The two placements are one charge at the gr.mesh, far smaller than the mesh.
    const std::vector<MemoryCharge> placed = charges_about(charges, "the primitive made here, placed 2 times");
    ASSERT_EQ(placed.size(), 1u);
    EXPECT_EQ(placed[0].where.line, 8);
    EXPECT_GT(placed[0].bytes, 2.0 * embree_instance_bytes);
    EXPECT_LT(placed[0].bytes, 0.1 * mesh_bytes);
    // The scene's own figure, for the photon stage's share of the budget, is the sum of the
    // scene's charges (the render's add its image).
    const RenderScene scene(*job.scene, flat);
    EXPECT_DOUBLE_EQ(scene.info().estimated_bytes, total_bytes(scene_memory_charges(*job.scene, flat)));
    expect_one_charge(charges, "the 16 x 16 image", 16.0 * 16.0 * 24.0, "gr.render", 13);
    // --layers: six layers of an image and its copy for the file, and over an accumulation their
    // double sums, besides the accumulator's 200 bytes and its estimate's 25.
    RenderJob layered = job;
    layered.apply_command_line({"--layers"});
    expect_one_charge(render_memory_charges(layered, flat), "the 16 x 16 image", 16.0 * 16.0 * (24.0 + 6.0 * 24.0),
                      "gr.render", 13);
    layered.apply_command_line({"--integrator", "progressive", "--passes", "4"});
    expect_one_charge(render_memory_charges(layered, flat), "the 16 x 16 image",
                      16.0 * 16.0 * (24.0 + 200.0 + 25.0 + 6.0 * (24.0 + 24.0)), "gr.render", 13);
}

TEST(RenderMemory, PhotonMapsKnownBeforeTheBuildAreCharged) {
    RenderJob job = caustica::testing::load_first_job(ball_scene);
    const FlatScene flat = flatten_scene(job);
    // --gi: 100 000 photons for each of the two lights with a quadratic falloff, at the gr.option.
    expect_one_charge(render_memory_charges(job, flat), "the photon map of --gi-num-photons 100000 for 2 lights",
                      photon_memory_bound(2.0 * 100000), "gr.option", 1);
    // Caustic photons through projection maps are checked once the maps are built; without maps
    // they are known now, charged to the gr.render when the command line asked for them.
    job.apply_command_line({"--caustic-num-photons", "5000"});
    EXPECT_TRUE(charges_about(render_memory_charges(job, flat), "the photon map of --caustic").empty());
    job.apply_command_line({"--projection-map", "off"});
    expect_one_charge(render_memory_charges(job, flat), "the photon map of --caustic-num-photons 5000 for 2 lights",
                      photon_memory_bound(2.0 * 5000), "gr.render", 9);
}

TEST(RenderMemory, ASceneOverTheBudgetIsRefusedBeforeAnythingIsBuilt) {
    constexpr int triangles = 20000;  // 3.6 MiB by the formula, against a budget of 1 MiB
    RenderJob job = caustica::testing::load_first_job(strip_scene(triangles));
    job.options.render_memory_mib = 1;
    RenderSession session;
    session.set_job(job);
    const std::string message = prepare_error(session);
    EXPECT_NE(message.find("scene.lua:8: gr.mesh: the mesh (20000 triangles, 60000 vertices) would take " +
                           mebibytes(strip_mesh_bytes(triangles)) + " once built"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("more than the renderer's memory budget of 1.0 MiB (--render-memory MiB raises it)"),
              std::string::npos)
        << message;
    EXPECT_EQ(session.stage_counters().scene_builds, 0);

    // The same scene under a budget it fits renders.
    job.options.render_memory_mib = 64;
    session.set_job(job);
    EXPECT_NO_THROW(session.prepare());
    EXPECT_EQ(session.stage_counters().scene_builds, 1);
    session.start();
    EXPECT_TRUE(session.wait());
    EXPECT_EQ(session.image().width, 16);
    EXPECT_EQ(session.image().height, 16);
}

TEST(RenderMemory, AScriptCannotRaiseTheRendererBudget) {
    caustica::testing::TempFolder folder("caustica_render_memory");
    const std::string path = folder.write("raise.lua", "gr.option('--render-memory 1000000')\n");
    const std::string error = caustica::testing::load_error(path);
    EXPECT_NE(error.find("raise.lua:1: gr.option: --render-memory is for the command line only"), std::string::npos)
        << error;
}

TEST(RenderMemory, TheImageIsChargedToItsRender) {
    // A 16384 x 16384 image is 6 GiB of floats before a single ray: refused at its gr.render under a
    // budget it does not fit, with its accumulation's sums when the job accumulates passes.
    RenderJob job = caustica::testing::load_first_job(strip_scene(10));
    job.width = job.height = 4096;
    const FlatScene flat = flatten_scene(job);
    expect_one_charge(render_memory_charges(job, flat), "the 4096 x 4096 image", 4096.0 * 4096.0 * 24.0, "gr.render", 13);
    job.apply_command_line({"--integrator", "progressive", "--passes", "8"});
    expect_one_charge(render_memory_charges(job, flat), "the 4096 x 4096 image", 4096.0 * 4096.0 * (24.0 + 200.0 + 25.0),
                      "gr.render", 13);
    job.options.render_memory_mib = 64;
    RenderSession session;
    session.set_job(job);
    const std::string message = prepare_error(session);
    EXPECT_NE(message.find("scene.lua:13: gr.render: the 4096 x 4096 image would take 3984.0 MiB once built"),
              std::string::npos)
        << message;
    EXPECT_EQ(session.stage_counters().scene_builds, 0);
}
