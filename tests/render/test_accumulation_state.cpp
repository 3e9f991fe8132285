// A saved progressive accumulation (core/render/accumulation_state.h; docs/OUTPUT.md, "Resuming
// an accumulation"): the file round-trips every field, a damaged, truncated or hostile file is
// refused with its reason before anything is allocated for it, a job that differs is refused by
// the part that differs, and a session that continues a saved accumulation ends with the bits of
// one that rendered every pass at once.
#include "core/render/accumulation_state.h"

#include "core/integrators/progressive_accumulator.h"
#include "core/io/png_io.h"
#include "core/render/render_session.h"

#include "tests/scene_test_helpers.h"
#include "tests/temp_folder.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <limits>
#include <string>

using namespace caustica;

namespace {

/// A 3 x 2 state whose every field holds a distinct value.
AccumulationState small_state() {
    AccumulationState s;
    s.key = {11, 22, 33, 3, 2};
    s.next_pass = 9;
    s.scale_pass = 8;
    s.scale2 = 0.375;
    s.first_radius = 0.25;
    s.radius = 0.125;
    s.typical_radius = 0.5;
    s.seed = 0x0123456789abcdefULL;
    s.photons_emitted = 123456;
    s.seconds = 4.5;
    s.sums.resize(6 * ProgressiveAccumulator::sums_per_pixel);
    for (std::size_t i = 0; i < s.sums.size(); ++i) s.sums[i] = static_cast<std::int64_t>(i * 7919) - 300;
    for (std::size_t p = 0; p < 6; ++p)
        s.sums[p * ProgressiveAccumulator::sums_per_pixel + ProgressiveAccumulator::sample_count_slot] =
            static_cast<std::int64_t>(p + 4);
    s.radius_factors = {1.0f, 0.5f, 0.25f, 0.125f, 0.0625f, 0.75f};
    s.adapted_sums.resize(6 * ProgressiveAccumulator::snapshot_slots);
    for (std::size_t i = 0; i < s.adapted_sums.size(); ++i) s.adapted_sums[i] = static_cast<std::int64_t>(i) * -3;
    return s;
}

/// The reason decoding `bytes` as a 3 x 2 state is refused with ("" when it is not).
std::string refusal(const std::string& bytes) {
    try {
        decode_accumulation_state(bytes, "out.exr.caustica-state", 3, 2);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

/// The glass ball focus, progressive with adaptive radii, `passes` passes of few photons.
RenderJob focus_job(int passes) {
    RenderJob job = caustica::testing::glass_ball_focus_job();
    job.options.caustic_num_photons = 4000;
    job.options.adaptive_radius = true;
    job.options.passes = passes;
    job.options.passes_given = true;
    return job;
}

/// Renders `job` to the end in a fresh session (continuing `from` when given).
Image render_to_end(RenderSession& session, const RenderJob& job, const AccumulationState* from = nullptr) {
    session.set_job(job);
    if (from)
        session.start_from(*from);
    else
        session.start();
    EXPECT_TRUE(session.wait());
    return session.image();
}

bool same_bits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(a.pixels[0])) == 0;
}

}  // namespace

TEST(AccumulationState, RoundTripsEveryField) {
    const AccumulationState s = small_state();
    const AccumulationState back = decode_accumulation_state(encode_accumulation_state(s), "x", 3, 2);
    EXPECT_EQ(back.key, s.key);
    EXPECT_EQ(back.next_pass, s.next_pass);
    EXPECT_EQ(back.scale_pass, s.scale_pass);
    EXPECT_EQ(back.scale2, s.scale2);
    EXPECT_EQ(back.first_radius, s.first_radius);
    EXPECT_EQ(back.radius, s.radius);
    EXPECT_EQ(back.typical_radius, s.typical_radius);
    EXPECT_EQ(back.seed, s.seed);
    EXPECT_EQ(back.photons_emitted, s.photons_emitted);
    EXPECT_EQ(back.seconds, s.seconds);
    EXPECT_EQ(back.sums, s.sums);
    EXPECT_EQ(back.radius_factors, s.radius_factors);
    EXPECT_EQ(back.adapted_sums, s.adapted_sums);
}

TEST(AccumulationState, WithoutRadiusFactorsTheFileIsHeaderSumsAndChecksum) {
    AccumulationState s = small_state();
    s.radius_factors.clear();
    s.adapted_sums.clear();
    const std::string bytes = encode_accumulation_state(s);
    EXPECT_EQ(bytes.size(), 128 + 6 * ProgressiveAccumulator::sums_per_pixel * 8 + 8);
    const AccumulationState back = decode_accumulation_state(bytes, "x", 3, 2);
    EXPECT_TRUE(back.radius_factors.empty());
    EXPECT_TRUE(back.adapted_sums.empty());
    EXPECT_EQ(back.sums, s.sums);
}

TEST(AccumulationState, ARadiusScaleIsTakenUpTo16AndRefusedBeyond) {
    // --auto-radius may raise the scale above 1, never above 16.
    for (double scale2 : {1e-12, 1.0, 4.5, 16.0}) {
        AccumulationState s = small_state();
        s.scale2 = scale2;
        EXPECT_EQ(decode_accumulation_state(encode_accumulation_state(s), "x", 3, 2).scale2, scale2);
    }
    for (double scale2 : {0.0, -1.0, 16.5, 1e300, std::numeric_limits<double>::infinity(),
                          std::numeric_limits<double>::quiet_NaN()}) {
        AccumulationState s = small_state();
        s.scale2 = scale2;
        EXPECT_NE(refusal(encode_accumulation_state(s)).find("a radius or time in its header is out of range"),
                  std::string::npos)
            << scale2;
    }
}

TEST(AccumulationState, EveryTruncationIsRefusedWithTheFileName) {
    const std::string bytes = encode_accumulation_state(small_state());
    for (std::size_t length : {std::size_t{0}, std::size_t{15}, std::size_t{127}, std::size_t{128}, std::size_t{135},
                               bytes.size() / 2, bytes.size() - 8, bytes.size() - 1}) {
        const std::string reason = refusal(bytes.substr(0, length));
        EXPECT_EQ(reason.rfind("out.exr.caustica-state: ", 0), 0u) << length << ": " << reason;
    }
    EXPECT_NE(refusal(bytes.substr(0, bytes.size() - 1)).find("truncated"), std::string::npos);
    EXPECT_NE(refusal(bytes + "x").find("declares"), std::string::npos);
}

TEST(AccumulationState, ADamagedByteIsRefusedByTheChecksum) {
    const std::string bytes = encode_accumulation_state(small_state());
    for (std::size_t at : {std::size_t{200}, bytes.size() / 2, bytes.size() - 9, bytes.size() - 1}) {
        std::string damaged = bytes;
        damaged[at] = static_cast<char>(damaged[at] ^ 0x10);
        EXPECT_NE(refusal(damaged).find("checksum"), std::string::npos) << at;
    }
    std::string not_state = bytes;
    not_state[0] = 'X';
    EXPECT_NE(refusal(not_state).find("not a caustica accumulation state"), std::string::npos);
    std::string version = bytes;
    version[16] = 2;
    EXPECT_NE(refusal(version).find("version 2"), std::string::npos);
}

TEST(AccumulationState, AHostileHeaderIsRefusedBeforeAnyAllocation) {
    // A 160-byte file claiming a 65536 x 65536 image (860 GB of sums): refused by the size it was
    // asked to read, fast, without allocating what the header declares.
    const std::string header = encode_accumulation_state(small_state()).substr(0, 160);
    std::string bytes = header;
    const std::int32_t side = 65536;
    std::memcpy(&bytes[32], &side, 4);
    std::memcpy(&bytes[36], &side, 4);
    const auto t0 = std::chrono::steady_clock::now();
    const std::string reason = refusal(bytes);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), caustica::testing::time_bound(0.5));
    EXPECT_NE(reason.find("it was saved for a 65536 x 65536 image, this render is 3 x 2"), std::string::npos) << reason;
    // Negative and absurd numbers in a header whose size is right.
    for (std::size_t offset : {std::size_t{32}, std::size_t{40}, std::size_t{44}}) {
        std::string hostile = encode_accumulation_state(small_state());
        const std::int32_t negative = -5;
        std::memcpy(&hostile[offset], &negative, 4);
        EXPECT_FALSE(refusal(hostile).empty()) << offset;
    }
}

TEST(AccumulationState, MoreSamplesThanPassesAreRefusedEvenWithAGoodChecksum) {
    AccumulationState s = small_state();
    s.sums[2 * ProgressiveAccumulator::sums_per_pixel + ProgressiveAccumulator::sample_count_slot] = s.next_pass + 1;
    EXPECT_NE(refusal(encode_accumulation_state(s)).find("pixel 2 has 10 samples of 9 passes"), std::string::npos);
    s = small_state();
    s.radius_factors[1] = -1.0f;
    EXPECT_NE(refusal(encode_accumulation_state(s)).find("radius factor"), std::string::npos);
}

TEST(AccumulationState, ReadsAFileAndRefusesAFolderOrAMissingFile) {
    caustica::testing::TempFolder folder("caustica_state");
    const std::string path = folder.file("out.exr.caustica-state");
    write_accumulation_state(path, small_state(), false);
    EXPECT_EQ(read_accumulation_state(path, 3, 2).sums, small_state().sums);
    EXPECT_THROW(read_accumulation_state(folder.path().string(), 3, 2), InputError);
    EXPECT_THROW(read_accumulation_state(folder.file("missing"), 3, 2), InputError);
}

TEST(AccumulationState, AJobIsRefusedByThePartThatDiffers) {
    const RenderJob job = focus_job(4);
    const AccumulationKey key = accumulation_key(job);
    auto mismatch = [&](const RenderJob& other) { return accumulation_mismatch(key, accumulation_key(other)); };
    // The stopping rules, the output's options and the threads do not change what a pass adds.
    RenderJob same = job;
    same.options.passes = 400;
    same.options.time_limit = 60.0;
    same.options.target_error = 0.01;
    same.options.threads = 3;
    same.options.exposure = 2.0;
    same.options.stats = true;
    EXPECT_EQ(mismatch(same), "");
    RenderJob photons = job;
    photons.options.caustic_num_photons = 8000;
    EXPECT_NE(mismatch(photons).find("other options"), std::string::npos);
    RenderJob camera = job;
    camera.camera.eye.x += 0.01;
    EXPECT_EQ(mismatch(camera), "it was saved for another camera");
    RenderJob scene = job;
    auto materials = std::make_shared<SceneDesc>(*job.scene);
    materials->materials.at(0).kd.x += 0.1;
    scene.scene = materials;
    EXPECT_NE(mismatch(scene).find("another scene"), std::string::npos);
    // A texture file edited under the same name: its decoded pixels are part of the scene.
    auto textured = [&](unsigned char texel) {
        auto desc = std::make_shared<SceneDesc>(*job.scene);
        auto png = std::make_shared<Png8>();
        png->width = png->height = 2;
        png->channels = 3;
        png->data.assign(12, 100);
        png->data[5] = texel;
        TextureDesc texture;
        texture.source = "/scenes/wood.png";
        texture.image = png;
        desc->textures.push_back(texture);
        RenderJob j = job;
        j.scene = desc;
        return j;
    };
    EXPECT_NE(accumulation_mismatch(accumulation_key(textured(1)), accumulation_key(textured(2))).find("another scene"),
              std::string::npos);
    EXPECT_EQ(accumulation_mismatch(accumulation_key(textured(1)), accumulation_key(textured(1))), "");
    RenderJob size = job;
    size.width = 41;
    EXPECT_EQ(mismatch(size), "it was saved for a 40 x 40 image, this render is 41 x 40");
}

TEST(AccumulationState, ContinuingASavedAccumulationGivesTheBitsOfOneRun) {
    // 12 passes at once against 6, saved to bytes and read back, then continued to 12 in another
    // session: the radius adaptation before pass 8 included.
    RenderSession whole_session;
    const Image whole = render_to_end(whole_session, focus_job(12));
    RenderSession first;
    const Image half = render_to_end(first, focus_job(6));
    AccumulationState saved;
    ASSERT_TRUE(first.accumulation_state(saved));
    EXPECT_EQ(saved.next_pass, 6);
    const AccumulationState read =
        decode_accumulation_state(encode_accumulation_state(saved), "state", saved.key.width, saved.key.height);
    RenderSession second;
    const Image continued = render_to_end(second, focus_job(12), &read);
    EXPECT_EQ(second.progress().passes_done, 12);
    EXPECT_TRUE(same_bits(continued, whole));
    EXPECT_FALSE(same_bits(half, whole));
    AccumulationState after;
    ASSERT_TRUE(second.accumulation_state(after));
    ASSERT_TRUE(whole_session.accumulation_state(saved));
    EXPECT_EQ(after.sums, saved.sums);
    EXPECT_EQ(after.radius_factors, saved.radius_factors);
    // Asking for no more passes than it holds shows the saved image, as it was.
    RenderSession third;
    EXPECT_TRUE(same_bits(render_to_end(third, focus_job(6), &read), half));
    // The photon grid's cell size is measured again, not read: a state whose header holds a tiny
    // one (the checksum made to match) continues to the same bits, in bounded time.
    AccumulationState tiny = read;
    tiny.typical_radius = 1e-9;
    const AccumulationState tiny_read =
        decode_accumulation_state(encode_accumulation_state(tiny), "state", tiny.key.width, tiny.key.height);
    RenderSession fourth;
    EXPECT_TRUE(same_bits(render_to_end(fourth, focus_job(12), &tiny_read), whole));
}

TEST(AccumulationState, ContinuingABalancedAccumulationGivesTheBitsOfOneRun) {
    // With the balanced radius: 6 passes saved (the sequence scaled before passes 4), continued to
    // 12 (scaled again before pass 8, from the continued sums and the saved sequence).
    auto balanced = [](int passes) {
        RenderJob job = focus_job(passes);
        job.options.adaptive_radius = false;
        job.options.auto_radius = true;
        return job;
    };
    RenderSession whole_session;
    const Image whole = render_to_end(whole_session, balanced(12));
    RenderSession first;
    render_to_end(first, balanced(6));
    AccumulationState saved;
    ASSERT_TRUE(first.accumulation_state(saved));
    EXPECT_NE(saved.scale2, 1.0);
    const AccumulationState read =
        decode_accumulation_state(encode_accumulation_state(saved), "state", saved.key.width, saved.key.height);
    EXPECT_EQ(read.scale2, saved.scale2);
    RenderSession second;
    EXPECT_TRUE(same_bits(render_to_end(second, balanced(12), &read), whole));
    RenderSession plain;
    RenderJob fixed = balanced(12);
    fixed.options.auto_radius = false;
    EXPECT_FALSE(same_bits(render_to_end(plain, fixed), whole));
}

TEST(AccumulationState, ASessionRefusesAnotherJobsAccumulation) {
    RenderSession session;
    render_to_end(session, focus_job(2));
    AccumulationState saved;
    ASSERT_TRUE(session.accumulation_state(saved));
    RenderJob other = focus_job(4);
    other.camera.eye.z += 0.5;
    RenderSession second;
    second.set_job(other);
    try {
        second.start_from(saved);
        FAIL() << "another camera's accumulation was continued";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("another camera"), std::string::npos) << e.what();
    }
}

namespace caustica {
namespace {

/// Continues the session's accumulation to `passes` (resume: the snapshot asked for survives).
void continue_to(RenderSession& session, int passes) {
    session.set_stop_rules(passes, 0.0, 0.0);
    ASSERT_TRUE(session.resume());
    ASSERT_TRUE(session.wait());
}

TEST(AccumulationState, ASnapshotIsOfTheNextWholePassAndAStaleOneIsNeverHandedOut) {
    RenderSession session;
    render_to_end(session, focus_job(2));
    // Asked for between renders: made at the end of the next pass (3), whatever ran after it.
    session.request_accumulation_snapshot();
    continue_to(session, 4);
    AccumulationState snapshot;
    ASSERT_TRUE(session.take_accumulation_snapshot(snapshot));
    EXPECT_EQ(snapshot.next_pass, 3);
    EXPECT_FALSE(session.take_accumulation_snapshot(snapshot)) << "a snapshot is handed out once";
    // One made (after pass 5) and never taken is stale once another is asked for: the new request
    // drops it, and nothing is handed out until the pass under way ends.
    session.request_accumulation_snapshot();
    continue_to(session, 6);
    session.request_accumulation_snapshot();
    EXPECT_FALSE(session.take_accumulation_snapshot(snapshot)) << "the snapshot of pass 5 was handed to a later request";
    continue_to(session, 7);
    ASSERT_TRUE(session.take_accumulation_snapshot(snapshot));
    EXPECT_EQ(snapshot.next_pass, 7);
    AccumulationState now;
    ASSERT_TRUE(session.accumulation_state(now));
    EXPECT_EQ(snapshot.key, now.key);
    EXPECT_EQ(snapshot.sums, now.sums);  // the 7 passes, as the session holds them
}

}  // namespace
}  // namespace caustica
