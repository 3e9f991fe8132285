// Fuzz target: scene script text -> SceneScript or InputError, in this process (the loader of
// the command line runs the script in a child process, which would hide a crash from the
// fuzzer). After a successful load the first render is made at 8 x 8 on one thread, so that
// scene flattening, the BVH build and a few rays see what the script made.
#include "fuzz/fuzz_support.h"
#include "fuzz/fuzz_targets.h"

#include "core/lua/scene_loader.h"
#include "core/io/png_io.h"
#include "core/render/render_session.h"
#include "core/scene/source_location.h"
#include "core/util/printable_text.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>
#include <thread>

namespace caustica::fuzz::scene_loader {

namespace {

/// A plane: two triangles in y = 0 (the course's plane.obj has the same shape).
constexpr const char* plane_obj = "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                  "f 1/1 2/2 3/3 4/4\n";
/// A tetrahedron: four triangles.
constexpr const char* solid_obj = "v 0 1 0\nv -1 -1 1\nv 1 -1 1\nv 0 -1 -1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n";

/// Mesh files the scenes of the seed corpus name (scenes/, the course scenes), made small.
constexpr const char* solid_names[] = {"buckyball.obj", "cow.obj",   "cube.obj",       "cylinder.obj",
                                       "dodeca.obj",    "icosa.obj", "smstdodeca.obj", "mickey.obj",
                                       "mesh.obj"};
/// Texture files the seeds name (scenes/textures.lua with its folder removed by make_corpus.sh).
constexpr const char* texture_names[] = {"bricks.png",  "bricks_bump.png", "colour_wheel.png", "compass.png",
                                         "die_unwrap.png", "globe.png",    "tex.png"};

/// The folder the scene file is written to, with the meshes and textures it may name.
std::string make_scene_folder() {
    const FuzzFolder& folder = FuzzFolder::get();
    std::filesystem::create_directories(folder.path() + "/scene");
    folder.write("scene/plane.obj", plane_obj);
    for (const char* name : solid_names) folder.write(std::string("scene/") + name, solid_obj);
    Image image(4, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) image.at(x, y) = (x + y) % 2 ? glm::vec3(0.9f, 0.2f, 0.1f) : glm::vec3(0.1f, 0.3f, 0.9f);
    for (const char* name : texture_names)
        write_png_atomic(folder.path() + "/scene/" + name, image, PixelEncoding::clamped_linear);
    return folder.path() + "/scene";
}

const std::string& scene_folder() {
    static const std::string path = make_scene_folder();
    return path;
}

/// The job made small and cheap: 8 x 8, one thread, no anti-aliasing, few photons, a 1 GiB render
/// budget. Everything else (camera, lights, materials, the other options) stays as the script made it.
RenderJob tiny(RenderJob job) {
    job.width = job.height = 8;
    Options& o = job.options;
    o.resolution_override = 0;
    o.threads = 1;
    o.silent = true;
    o.reproducible = true;
    o.disable_aa = true;
    o.caustic_num_photons = std::min<long long>(o.caustic_num_photons, 2000);
    o.shadow_grid = std::min(o.shadow_grid, 2);
    o.max_depth = std::min(o.max_depth, 4);
    o.render_memory_mib = 1024;  // what the renderer builds stays within the target's 2 GiB process bound
    return job;
}

/// Longest an 8 x 8 render (scene build included) may take before it counts as a hang. Hangs of
/// the loader itself show as libFuzzer timeouts instead (scripts/fuzz.sh tells them apart).
constexpr double render_limit_seconds = 15.0;

void render_first_job(const RenderJob& job) {
    RenderSession session;
    session.set_job(tiny(job));
    try {
        session.start();
        const auto started = std::chrono::steady_clock::now();
        while (session.progress().running) {
            const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - started;
            fuzz_require(elapsed.count() < render_limit_seconds, "an 8 x 8 render finishes within 15 s");
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        if (!session.wait()) return;
    } catch (const InputError&) {
        return;  // the documented refusal of a scene the renderer cannot draw
    }
    const Image& image = session.image();
    fuzz_require(image.width == 8 && image.height == 8, "the image has the size asked for");
    for (const glm::vec3& p : image.pixels)
        fuzz_require(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z),
                     "no NaN or Inf reaches the image (absurd magnitudes are refused)");
}

/// Text a script chose reaches the user bounded and with nothing a terminal would act on
/// (docs/RELIABILITY.md, "Script text reaches the user bounded and visible").
void require_shown_safely(const std::string& text, const char* what) {
    fuzz_require(text.size() <= printable_text_max_bytes(shown_message_limit),
                 (std::string(what) + " is bounded").c_str());
    fuzz_require(printable_text(text, text.size() + 1) == text,
                 (std::string(what) + " holds no control or escape character").c_str());
}

}  // namespace

int fuzz_one(const std::uint8_t* data, std::size_t size) {
    scene_folder();  // made on the first input
    const std::string path = FuzzFolder::get().write("scene/fuzz.lua", data, size);
    LoadSettings settings;
    settings.timeout_seconds = 1.0;
    settings.memory_limit_bytes = std::size_t(256) << 20;
    settings.base_options.silent = true;
    SceneScript script;
    try {
        script = load_scene_script_in_process(path, settings);
    } catch (const InputError& e) {
        require_shown_safely(e.what(), "a refusal's message");
        return 0;
    }
    for (const std::string& warning : script.warnings) require_shown_safely(warning, "a warning");
    if (!script.renders.empty()) render_first_job(script.renders.front());
    return 0;
}

}  // namespace caustica::fuzz::scene_loader
