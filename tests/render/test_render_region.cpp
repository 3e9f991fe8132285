// A render region (docs/PREVIEW.md, "Render region"): the passes render its pixels alone, the
// others keep what they hold, an accumulation continues in it without restarting, each pass
// costs samples of its pixels only, and the error estimate looks at it alone.
#include "tests/scene_test_helpers.h"
#include "tests/test_support.h"

#include "core/integrators/progressive_accumulator.h"
#include "core/render/render_session.h"

#include <gtest/gtest.h>

#include <cstdint>

using namespace caustica;

namespace {

/// The glass and mirror balls (48 x 48, --reproducible) with `options`: caustics of both kinds.
RenderJob balls_job(const std::string& options) {
    return caustica::testing::glass_and_mirror_balls_job(options);
}

/// Renders `job` whole in a fresh session, up to `passes` passes when it accumulates.
Image render_whole(const RenderJob& job, int passes) {
    RenderSession session;
    session.set_job(job);
    if (passes > 0) session.set_stop_rules(passes, 0.0, 0.0);
    session.start();
    EXPECT_TRUE(session.wait());
    return session.image();
}

/// How many pixels of `region` differ between two images of its size.
int pixels_differing_inside(const Image& a, const Image& b, const RenderRegion& region) {
    int differing = 0;
    for (int y = region.y0; y < region.y1; ++y)
        for (int x = region.x0; x < region.x1; ++x) differing += a.at(x, y) != b.at(x, y) ? 1 : 0;
    return differing;
}

/// Whether every pixel of `image` is `inside`'s within the region and `outside`'s elsewhere (bit for bit).
void expect_region_composite(const Image& image, const Image& inside, const Image& outside, const RenderRegion& region) {
    int wrong_inside = 0, wrong_outside = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const bool in = region.renders(x, y);
            if (image.at(x, y) != (in ? inside : outside).at(x, y)) ++(in ? wrong_inside : wrong_outside);
        }
    EXPECT_EQ(wrong_inside, 0) << "pixels inside the region that are not the whole render's";
    EXPECT_EQ(wrong_outside, 0) << "pixels outside the region that changed";
}

}  // namespace

// Two passes over the whole image, then a region and two more passes (resume): outside, the
// two-pass image bit for bit; inside, the image of four uninterrupted passes bit for bit (the
// accumulation went on, its sums kept); the two region passes traced one sample per region pixel
// each, where the whole passes traced one per image pixel.
TEST(RenderRegion, AccumulationPassesGoToTheRegionAloneAndContinueItsSums) {
    const RenderJob job = balls_job("--integrator progressive --caustic-num-photons 20000");
    const RenderRegion region{8, 12, 24, 28};
    RenderSession session;
    session.set_job(job);
    session.set_stop_rules(2, 0.0, 0.0);
    session.start();
    ASSERT_TRUE(session.wait());
    const Image two_passes = session.image();
    const std::uint64_t whole_samples = session.stats().rays.samples;
    EXPECT_EQ(whole_samples, 2u * 48u * 48u);

    session.set_region(region);
    session.set_stop_rules(4, 0.0, 0.0);
    ASSERT_TRUE(session.resume()) << "a region must not restart the accumulation";
    ASSERT_TRUE(session.wait());
    EXPECT_EQ(session.progress().passes_done, 4);
    const std::uint64_t region_samples = session.stats().rays.samples;
    EXPECT_EQ(region_samples, 2u * 16u * 16u);

    const Image four_passes = render_whole(job, 4);
    EXPECT_GT(pixels_differing_inside(four_passes, two_passes, region), 0) << "the passes change nothing to test";
    expect_region_composite(session.image(), four_passes, two_passes, region);
}

// The classic integrator has no passes to continue: its render of another job with a region
// renders the region alone, as a whole render of that job would, and leaves the other pixels as
// the last render left them, tracing a fraction of the samples.
TEST(RenderRegion, ClassicRendersTheRegionAloneAndKeepsTheOtherPixels) {
    const RenderJob before = balls_job("--caustic-num-photons 20000");
    RenderJob after = before;
    after.ambient = glm::dvec3(0.25);
    const RenderRegion region{30, 4, 42, 16};  // 144 of 2304 pixels
    RenderSession session;
    session.set_job(before);
    session.start();
    ASSERT_TRUE(session.wait());
    const Image first = session.image();
    const std::uint64_t whole_samples = session.stats().rays.samples;

    session.set_region(region);
    session.set_job(after);
    session.start();
    ASSERT_TRUE(session.wait());
    const std::uint64_t region_samples = session.stats().rays.samples;
    // Four corner samples a pixel and at most five more where it is anti-aliased: the region's
    // 144 pixels cost at most 1296 samples, the image's first pass alone 9216.
    EXPECT_GT(region_samples, 0u);
    EXPECT_LT(region_samples * 4, whole_samples);

    const Image whole_after = render_whole(after, 0);
    EXPECT_GT(pixels_differing_inside(whole_after, first, region), 0) << "the change changes nothing to test";
    expect_region_composite(session.image(), whole_after, first, region);

    // Cleared, the region renders the whole image again.
    session.set_region({});
    session.start();
    ASSERT_TRUE(session.wait());
    EXPECT_GE(session.stats().rays.samples, 4u * 48u * 48u);  // four corners of every pixel
    expect_region_composite(session.image(), whole_after, whole_after, {});
}

// The estimate of the error looks at the region's pixels alone: two pixels whose passes all give
// the same value have no error; two beside them whose passes alternate have some.
TEST(RenderRegion, ErrorEstimateLooksAtTheRegionAlone) {
    ProgressiveAccumulator accumulator;
    accumulator.reset(4, 1);
    for (int pass = 0; pass < 8; ++pass)
        for (std::size_t pixel = 0; pixel < 4; ++pixel) {
            const double value = pixel < 2 ? 0.5 : (pass % 2 == 0 ? 0.2 : 0.8);
            PassSample sample;
            sample.colour = glm::vec3(static_cast<float>(value));
            sample.photon = sample.photon_inner = value;
            sample.group = pass % replicate_groups;
            accumulator.add(pixel, sample);
        }
    const ErrorEstimate whole = accumulator.estimate_error();
    const ErrorEstimate steady = accumulator.estimate_error(RenderRegion{0, 0, 2, 1});
    const ErrorEstimate alternating = accumulator.estimate_error(RenderRegion{2, 0, 4, 1});
    ASSERT_TRUE(whole.known);
    ASSERT_TRUE(steady.known);
    ASSERT_TRUE(alternating.known);
    EXPECT_EQ(whole.region_pixels, 4u);
    EXPECT_EQ(steady.region_pixels, 2u);
    EXPECT_EQ(alternating.region_pixels, 2u);
    EXPECT_GT(whole.relative, 0.0);
    EXPECT_EQ(steady.relative, 0.0);
    EXPECT_GT(alternating.relative, whole.relative);
}
