// Every course scene renders with --a4 at the size it asks, and objects appear where the camera
// model says they must: each primitive's centre, projected with the scene's camera, shows a
// surface (not the miss colour), and the image corners away from all objects show the miss colour.
// The scenes are those of ../shared/cs488: without it these tests skip (course_scenes.h).
#include "core/scene/camera.h"
#include "core/lua/scene_loader.h"
#include "core/render/render_session.h"
#include "core/scene/scene_flatten.h"
#include "tests/course_scenes.h"

#include <gtest/gtest.h>

#include <string>

using namespace caustica;

namespace {

struct CourseCase {
    const char* file;
    int width, height;
    std::size_t lights;
    std::size_t primitives;  // after instancing
};

void PrintTo(const CourseCase& c, std::ostream* os) { *os << c.file; }

class CourseScene : public ::testing::TestWithParam<CourseCase> {};

glm::vec3 primitive_centre(const SceneDesc& scene, const PlacedPrimitive& p) {
    glm::vec3 lo, hi;
    if (p.is_mesh) {
        const MeshData& mesh = *scene.meshes[p.mesh];
        lo = hi = mesh.positions[0];
        for (const glm::vec3& v : mesh.positions) lo = glm::min(lo, v), hi = glm::max(hi, v);
    } else {
        shape_bounds(p.shape, lo, hi);
    }
    return glm::vec3(p.object_to_world * glm::dvec4(glm::dvec3(0.5f * (lo + hi)), 1.0));
}

}  // namespace

TEST_P(CourseScene, RendersWithObjectsWhereTheCameraPutsThem) {
    CAUSTICA_SKIP_WITHOUT_CS488();
    const CourseCase c = GetParam();
    LoadSettings settings;
    settings.base_options.a4 = true;
    const SceneScript script = load_scene_script(caustica::testing::cs488_file(c.file), settings);
    ASSERT_EQ(script.renders.size(), 1u);
    RenderJob job = script.renders[0];
    EXPECT_EQ(job.width, c.width);
    EXPECT_EQ(job.height, c.height);
    EXPECT_EQ(job.lights.size(), c.lights);
    ASSERT_TRUE(job.options.a4);
    job.options.silent = true;
    job.options.reproducible = true;

    RenderSession session;
    session.set_job(job);
    session.start();
    ASSERT_TRUE(session.wait());
    const Image& image = session.image();
    ASSERT_EQ(image.width, c.width);
    ASSERT_EQ(image.height, c.height);

    const FlatScene flat = flatten_scene(*job.scene, job.root, true);
    EXPECT_EQ(flat.primitives.size(), c.primitives);
    const Camera camera(job.camera, job.width, job.height);
    const glm::vec3 miss(job.miss_colour);
    int checked = 0;
    for (const PlacedPrimitive& p : flat.primitives) {
        glm::vec2 pixel;
        if (!camera.project(primitive_centre(*job.scene, p), pixel)) continue;
        const int x = static_cast<int>(pixel.x), y = static_cast<int>(pixel.y);
        if (x < 0 || y < 0 || x >= image.width || y >= image.height) continue;
        EXPECT_NE(image.at(x, y), miss) << c.file << ": node '" << job.scene->nodes[p.node].name << "' at pixel "
                                        << x << "," << y << " shows the background";
        ++checked;
    }
    EXPECT_GE(checked, 3) << "too few primitives in view to check " << c.file;
}

INSTANTIATE_TEST_SUITE_P(Cs488, CourseScene,
                         ::testing::Values(CourseCase{"simple.lua", 256, 256, 2, 5},
                                           CourseCase{"nonhier.lua", 256, 256, 2, 7},
                                           CourseCase{"hier.lua", 256, 256, 2, 5},
                                           CourseCase{"simple-cows.lua", 256, 256, 1, 41},
                                           CourseCase{"macho-cows.lua", 256, 256, 1, 23}),
                         [](const ::testing::TestParamInfo<CourseCase>& info) {
                             std::string name = info.param.file;
                             return name.substr(0, name.find('.')) == "simple-cows"   ? std::string("simple_cows")
                                    : name.substr(0, name.find('.')) == "macho-cows" ? std::string("macho_cows")
                                                                                     : name.substr(0, name.find('.'));
                         });

TEST(CourseScenes, MissColourCornersInSimple) {
    CAUSTICA_SKIP_WITHOUT_CS488();
    LoadSettings settings;
    settings.base_options.a4 = true;
    RenderJob job = load_scene_script(caustica::testing::cs488_file("simple.lua"), settings).renders.at(0);
    job.options.silent = true;
    RenderSession session;
    session.set_job(job);
    session.start();
    ASSERT_TRUE(session.wait());
    // The top corners look past every sphere. simple.lua sets no miss colour, so they show the
    // default: the default miss colour is white (1,1,1).
    EXPECT_EQ(session.image().at(0, 0), glm::vec3(1.0f));
    EXPECT_EQ(session.image().at(255, 0), glm::vec3(1.0f));
}
