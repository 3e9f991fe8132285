// --layers (docs/OUTPUT.md, "Layers"): the light layers sum to the image, the image is the same bits
// with and without them, albedo and normal are the first surface's kd and normal, and the
// multilayer OpenEXR holds every layer under its name.
#include "core/io/image_io.h"
#include "core/render/render_layers.h"
#include "core/render/render_session.h"
#include "tests/exr_channels.h"
#include "tests/scene_test_helpers.h"
#include "tests/temp_folder.h"
#include "tests/test_support.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

namespace caustica {
namespace {

using testing::glass_and_mirror_balls_job;
using testing::JobBuilder;

struct Rendered {
    Image image;
    std::vector<LayerImage> layers;
};

Rendered render_with_layers(const RenderJob& job) {
    RenderSession session;
    session.set_job(job);
    session.start();
    EXPECT_TRUE(session.wait());
    return {session.image(), session.layers()};
}

const Image& layer_of(const Rendered& r, ShadingLayer layer) {
    for (const LayerImage& l : r.layers)
        if (l.layer == layer) return l.image;
    throw std::logic_error(std::string("no layer ") + layer_name(layer));
}

/// The balls scene with every kind of light: the lights, an ambient term, caustics through the
/// glass and off the mirror, and a grey background seen past the floor's edge and in the mirror.
RenderJob every_kind_of_light(const std::string& options) {
    RenderJob job = glass_and_mirror_balls_job(options + " --caustic-num-photons 20000");
    job.ambient = glm::dvec3(0.1);
    job.miss_colour = glm::dvec3(0.3, 0.4, 0.5);
    job.options.layers = true;
    return job;
}

/// Checks that direct + indirect + caustic + background is the image at every pixel (within float
/// rounding: the terms are added in another order), that the image is the one rendered without
/// layers, bit for bit, and that each light layer holds something.
void expect_layers_sum_to_the_image(const RenderJob& job) {
    const auto start = std::chrono::steady_clock::now();
    const Rendered r = render_with_layers(job);
    RenderJob plain = job;
    plain.options.layers = false;
    const Image without = testing::render(plain);
    ASSERT_EQ(r.layers.size(), std::size(written_layers));
    ASSERT_EQ(r.image.pixels.size(), without.pixels.size());
    EXPECT_TRUE(r.image.pixels == without.pixels) << "--layers changed the image";
    std::map<ShadingLayer, float> brightest;
    double worst = 0.0;
    for (std::size_t i = 0; i < r.image.pixels.size(); ++i) {
        glm::vec3 sum(0.0f), magnitude(0.0f);
        for (ShadingLayer l : {ShadingLayer::direct, ShadingLayer::indirect, ShadingLayer::caustic, ShadingLayer::background}) {
            const glm::vec3 v = layer_of(r, l).pixels[i];
            sum += v;
            magnitude += glm::abs(v);
            brightest[l] = std::max({brightest[l], v.x, v.y, v.z});
        }
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(double(sum[c]) - r.image.pixels[i][c]) / (1.0 + magnitude[c]));
    }
    EXPECT_LT(worst, 1e-5);  // a few float roundings of values up to the caustic's focus
    for (const auto& [layer, value] : brightest) EXPECT_GT(value, 0.01f) << layer_name(layer);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), testing::time_bound(20.0));
}

TEST(Layers, ClassicLayersSumToTheImage) { expect_layers_sum_to_the_image(every_kind_of_light("")); }

TEST(Layers, ProgressiveLayersSumToTheImage) {
    expect_layers_sum_to_the_image(every_kind_of_light("--integrator progressive"));
}

TEST(Layers, ProgressiveAccumulationLayersSumToTheImage) {
    expect_layers_sum_to_the_image(every_kind_of_light("--integrator progressive --passes 4 --reproducible"));
}

/// The largest difference between two images, relative to 1 + the value.
double largest_difference(const Image& a, const Image& b) {
    double worst = 0.0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(double(a.pixels[i][c]) - b.pixels[i][c]) / (1.0 + std::abs(b.pixels[i][c])));
    return worst;
}

TEST(Layers, ShowLayerRendersTheLayerAsTheImage) {
    // One pass of classic without anti-aliasing (whose pixels --show-layer would choose from the
    // layer itself): the same computations as the --layers file's, so the same bits.
    const RenderJob classic = every_kind_of_light("--disable-aa");
    const Rendered with_layers = render_with_layers(classic);
    for (ShadingLayer layer : written_layers) {
        RenderJob shown = classic;
        shown.options.layers = false;
        shown.options.show_layer = layer;
        const Image image = testing::render(shown);
        ASSERT_EQ(image.pixels.size(), layer_of(with_layers, layer).pixels.size());
        EXPECT_TRUE(image.pixels == layer_of(with_layers, layer).pixels) << layer_name(layer);
    }
    // Progressive passes accumulate the shown layer as they do the image (in fixed point, where
    // the layers of --layers are double sums: a rounding apart).
    const RenderJob passes = every_kind_of_light("--integrator progressive --passes 4 --reproducible");
    const Rendered accumulated = render_with_layers(passes);
    for (ShadingLayer layer : {ShadingLayer::caustic, ShadingLayer::direct, ShadingLayer::normal}) {
        RenderJob shown = passes;
        shown.options.layers = false;
        shown.options.show_layer = layer;
        EXPECT_LT(largest_difference(testing::render(shown), layer_of(accumulated, layer)), 1e-6) << layer_name(layer);
    }
}

TEST(Layers, AShownLayerRefusesADebugViewBeforeRendering) {
    Options o;
    o.show_layer = ShadingLayer::direct;
    EXPECT_NO_THROW(check_shown_layer(o));
    o.draw_caustics_only = true;  // classic would show the caustic estimate, progressive black
    EXPECT_THROW(check_shown_layer(o), InputError);
    o.show_layer = ShadingLayer::beauty;
    EXPECT_NO_THROW(check_shown_layer(o));
    // The session refuses it too (the preview takes such a change back), naming the option.
    RenderJob job = every_kind_of_light("--draw-gi-only --show-layer caustic");
    job.options.layers = false;
    RenderSession session;
    session.set_job(job);
    session.start();
    try {
        session.wait();
        FAIL() << "a shown layer with a debug view rendered";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("--show-layer: a debug view"), std::string::npos) << e.what();
    }
}

TEST(Layers, AlbedoIsKdAndTheNormalFacesTheCamera) {
    for (const char* integrator : {"classic", "progressive"}) {
        JobBuilder b(65, 65);  // odd: the centre pixel's ray is exactly the axis
        const glm::dvec3 kd(0.5, 0.25, 0.125);
        b.add(NodeKind::sphere, b.material(kd));
        b.camera({0, 0, 5}, {0, 0, -1}, 30);
        b.light({0, 0, 5}, {1, 1, 1});
        b.job.options.disable_aa = true;
        b.job.options.layers = true;
        b.job.options.integrator = std::string(integrator) == "classic" ? IntegratorKind::classic : IntegratorKind::progressive;
        const Rendered r = render_with_layers(b.build());
        const glm::vec3 normal = layer_of(r, ShadingLayer::normal).at(32, 32);
        EXPECT_NEAR(normal.x, 0.0f, 1e-4f) << integrator;
        EXPECT_NEAR(normal.y, 0.0f, 1e-4f) << integrator;
        EXPECT_NEAR(normal.z, 1.0f, 1e-4f) << integrator;
        EXPECT_EQ(layer_of(r, ShadingLayer::albedo).at(32, 32), glm::vec3(kd)) << integrator;
        // Lit head-on from the eye: all direct light, Lambert's kd (docs/SCENE_LANGUAGE.md, "Phong").
        const glm::vec3 direct = layer_of(r, ShadingLayer::direct).at(32, 32);
        EXPECT_NEAR(direct.x, 0.5f, 1e-4f) << integrator;
        // A corner pixel misses: the miss colour (white) is background, and there is no surface.
        EXPECT_EQ(layer_of(r, ShadingLayer::background).at(0, 0), glm::vec3(1.0f)) << integrator;
        EXPECT_EQ(layer_of(r, ShadingLayer::albedo).at(0, 0), glm::vec3(0.0f)) << integrator;
        EXPECT_EQ(layer_of(r, ShadingLayer::normal).at(0, 0), glm::vec3(0.0f)) << integrator;
        EXPECT_EQ(layer_of(r, ShadingLayer::direct).at(0, 0), glm::vec3(0.0f)) << integrator;
    }
}

TEST(Layers, WithoutTheOptionNoLayerIsRendered) {
    RenderJob job = every_kind_of_light("");
    job.options.layers = false;
    EXPECT_TRUE(render_with_layers(job).layers.empty());
}

TEST(Layers, TheMultilayerExrHoldsEveryLayerByNameAndTheySum) {
    const Rendered r = render_with_layers(every_kind_of_light(""));
    testing::TempFolder folder;
    const std::string path = folder.file("layers.exr");
    std::vector<Image> scaled;
    write_exr_channels_atomic(path, r.image.width, r.image.height, layer_channels(r.image, r.layers, 1.0f, scaled),
                              ExrPixel::float32, {{"caustica:integrator", "classic"}});
    int width = 0, height = 0;
    const std::map<std::string, std::vector<float>> channels = testing::read_exr_channels(path, width, height);
    ASSERT_EQ(width, r.image.width);
    ASSERT_EQ(height, r.image.height);
    std::vector<std::string> names;
    for (const auto& [name, values] : channels) names.push_back(name);
    const std::vector<std::string> expected = {
        "A",           "B",           "G",          "R",          "albedo.B",     "albedo.G",     "albedo.R",
        "background.B", "background.G", "background.R", "caustic.B", "caustic.G", "caustic.R", "direct.B",
        "direct.G",    "direct.R",    "indirect.B", "indirect.G", "indirect.R",   "normal.X",     "normal.Y",
        "normal.Z"};
    EXPECT_EQ(names, expected);  // OpenEXR lists channels sorted by name
    const Image& albedo = layer_of(r, ShadingLayer::albedo);
    for (std::size_t i = 0; i < r.image.pixels.size(); ++i) {
        EXPECT_EQ(channels.at("A")[i], 1.0f);
        // --exposure 1 doubles the image and the light layers, not the albedo.
        EXPECT_EQ(channels.at("G")[i], 2.0f * r.image.pixels[i].y);
        EXPECT_EQ(channels.at("albedo.G")[i], albedo.pixels[i].y);
        const float sum = channels.at("direct.G")[i] + channels.at("indirect.G")[i] + channels.at("caustic.G")[i] +
                          channels.at("background.G")[i];
        EXPECT_NEAR(sum, channels.at("G")[i], 1e-5f * (2.0f + std::abs(sum))) << i;
    }
}

TEST(Layers, OnlyAnOpenExrWithoutADebugViewCanHoldLayers) {
    Options o;
    o.layers = true;
    EXPECT_EQ(layers_refusal(o, "out.exr"), "");
    EXPECT_EQ(layers_refusal(o, "out.EXR"), "");
    EXPECT_EQ(layers_refusal(o, "out.png"),
              "--layers: 'out.png': layers need an OpenEXR output (.exr); PNG and PFM hold one image");
    EXPECT_NE(layers_refusal(o, "out.pfm"), "");
    o.integrator = IntegratorKind::progressive;
    EXPECT_EQ(layers_refusal(o, "out.exr"), "");  // one pass
    o.passes = 4;
    EXPECT_EQ(layers_refusal(o, "out.exr"), "");  // an accumulation
    o.passes = 1;
    o.draw_caustics_only = true;
    EXPECT_NE(layers_refusal(o, "out.exr").find("debug view"), std::string::npos);
    o.draw_caustics_only = false;
    o.show_layer = ShadingLayer::caustic;
    EXPECT_NE(layers_refusal(o, "out.exr").find("--show-layer"), std::string::npos);
}

}  // namespace
}  // namespace caustica
