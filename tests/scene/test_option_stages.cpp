// Every option declares the stages its value feeds (core/scene/options.h, OptionStage). This walks
// the whole option table: for each option, on a classic job with caustic photons and progressive
// jobs with caustic photons and with GI paths, it changes the value and checks
//   - that the session re-runs exactly the declared stages (its stage counters), and
//   - that what the option does not declare does not change: the photon maps, built from scratch,
//     are the same photons when it does not feed the photon stage, and the rendered image is the
//     same bits when it feeds no stage up to the image.
// A missing declaration would be a stale cache (the preview showing an old photon map); a needless
// one, work redone for nothing.
#include "core/integrators/registry.h"
#include "core/photons/caustic_stage.h"
#include "core/geometry/render_scene.h"
#include "core/render/render_session.h"
#include "core/scene/options.h"
#include "core/scene/scene_flatten.h"
#include "tests/scene_test_helpers.h"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <map>

namespace caustica {
namespace {

using testing::glass_and_mirror_balls_job;

/// A value for each option other than the base jobs' (the first that changes the option's text).
/// Every option of the table must be here: a new option is walked too.
const std::map<std::string, std::vector<std::string>>& other_values() {
    static const std::map<std::string, std::vector<std::string>> values = {
        {"integrator", {"--integrator progressive", "--integrator classic"}},
        {"a4", {"--a4"}},
        {"timing", {"-t"}},
        {"silent", {}},  // on in both base jobs: turned off below
        {"stats", {"-S"}},
        {"verbose", {"-v"}},
        {"debug", {"-d"}},
        {"quality", {"--quality draft"}},
        {"disable-aa", {"--disable-aa"}},
        {"aa-grid", {"--aa-grid 2", "--aa-grid 4"}},
        {"aa-threshold", {"--aa-threshold 0.01"}},
        {"draw-aa", {"--draw-aa"}},
        {"reproducible", {}},  // on in both base jobs: turned off below
        {"passes", {"--passes 2", "--passes 1"}},
        {"time", {"--time 1000"}},
        {"target-error", {"--target-error 0.5"}},
        {"seed", {"--seed 7"}},
        {"threads", {"--threads 1"}},
        {"disable-bv", {"--disable-bv"}},
        {"disable-csg-bb", {"--disable-csg-bb"}},
        {"max-depth", {"--max-depth 2"}},
        {"min-weight", {"--min-weight 0.3"}},
        {"roulette-weight", {"--roulette-weight 0.3"}},
        {"no-soft-shadows", {"--no-soft-shadows"}},
        {"shadow-grid", {"--shadow-grid 2"}},
        {"rays", {"--rays"}},
        {"srgb", {"--srgb"}},
        {"tonemap", {"--tonemap filmic"}},
        {"show-layer", {"--show-layer caustic"}},
        {"exposure", {"--exposure 1"}},
        {"exr-pixel", {"--exr-pixel float"}},
        {"layers", {"--layers"}},
        {"minres", {"--minres"}},
        {"lores", {"--lores"}},
        {"midres", {"--midres"}},
        {"hires", {"--hires"}},
        {"script-timeout", {"--script-timeout 5"}},
        {"script-memory", {"--script-memory 100"}},
        {"render-memory", {"--render-memory 100000"}},
        {"caustic-num-photons", {"--caustic-num-photons 30000"}},
        {"caustic-num-neighbours", {"--caustic-num-neighbours 12"}},
        {"caustic-pm-gran", {"--caustic-pm-gran 40"}},
        {"caustic-max-dist", {"--caustic-max-dist 0.1"}},
        {"accumulation-radius", {"--accumulation-radius 1"}},
        {"radius-alpha", {"--radius-alpha 1"}},
        {"projection-map", {"--projection-map off"}},
        {"caustic-filter", {"--caustic-filter cone"}},
        {"adaptive-radius", {"--adaptive-radius on"}},
        {"auto-radius", {"--auto-radius on"}},
        {"photon-split", {"--photon-split on"}},
        {"guided-emission", {"--guided-emission off"}},
        {"photons-per-pixel", {"--photons-per-pixel 2"}},
        {"photon-emission", {"--photon-emission random"}},
        {"unit-distance", {"--unit-distance 2"}},
        {"energy-fudge", {"--energy-fudge 2"}},
        {"draw-caustic-map", {"--draw-caustic-map"}},
        {"draw-caustic-prm", {"--draw-caustic-prm"}},
        {"show-projection-map", {"--show-projection-map"}},
        {"draw-caustics-only", {"--draw-caustics-only"}},
        {"no-caustic-map", {"--no-caustic-map"}},
        {"gi", {"--gi"}},  // on in the GI job: turned off below
        {"gi-num-photons", {"--gi-num-photons 3000"}},
        {"gi-num-neighbours", {"--gi-num-neighbours 20"}},
        {"draw-gi-map", {"--draw-gi-map"}},
        {"draw-gi-only", {"--draw-gi-only"}},
    };
    return values;
}

/// `base` with the option `name` changed.
RenderJob changed(const RenderJob& base, const std::string& name) {
    RenderJob job = base;
    Options& o = job.options;
    if (name == "silent") o.silent = false;
    if (name == "reproducible") o.reproducible = false;
    const bool turned_off = (name == "gi" && o.gi);
    if (turned_off) o.gi = false;
    for (const std::string& text : other_values().at(name)) {
        if (turned_off) break;
        apply_option_tokens(o, split_option_string(text));
        if (describe_non_default(o) != describe_non_default(base.options)) break;
        o = base.options;
    }
    EXPECT_NE(describe_non_default(o), describe_non_default(base.options)) << "--" << name << " did not change";
    const int size = o.resolution_override;
    if (size > 0) job.width = job.height = size;  // as RenderSession::set_job does
    return job;
}

/// The photons of a job's photon stage, built from scratch: caustic map then GI map.
std::vector<Photon> stage_photons_of(const RenderJob& job) {
    const RenderScene scene(*job.scene, flatten_scene(job));
    CausticStage stage;
    if (caustics_needed(job)) build_caustic_stage(stage, scene, job, nullptr);
    std::vector<Photon> photons;
    for (const PhotonMap* map : {stage.map.get(), stage.gi_map.get()})
        if (map) photons.insert(photons.end(), map->photons().begin(), map->photons().end());
    return photons;
}

bool same_photons(const std::vector<Photon>& a, const std::vector<Photon>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(Photon)) == 0);
}

bool same_pixels(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height) return false;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            if (std::memcmp(&a.at(x, y), &b.at(x, y), sizeof(glm::vec3)) != 0) return false;
    return true;
}

Image rendered(RenderSession& session) {
    session.start();
    EXPECT_TRUE(session.wait());
    return session.image();
}

class OptionWalk : public ::testing::TestWithParam<const char*> {
protected:
    RenderJob base() const {
        RenderJob job = glass_and_mirror_balls_job(std::string(GetParam()) + " --caustic-num-photons 20000 --caustic-max-dist 1");
        job.width = job.height = 24;
        return job;
    }
};

TEST(OptionStageTable, EveryOptionIsWalked) {
    for (const OptionStages& option : option_stages())
        EXPECT_TRUE(other_values().count(option.name)) << "--" << option.name << " has no value to walk to";
    EXPECT_EQ(other_values().size(), option_stages().size());
}

TEST_P(OptionWalk, ChangingAnOptionReRunsExactlyTheStagesItFeeds) {
    const RenderJob job = base();
    ASSERT_TRUE(caustics_needed(job));
    const std::vector<Photon> base_photons = stage_photons_of(job);
    ASSERT_FALSE(base_photons.empty());
    // One session holds the base job's stages between options, as the preview's does.
    RenderSession session;
    session.set_job(job);
    const Image base_image = rendered(session);
    int changed_photons = 0, changed_images = 0;
    for (const OptionStages& option : option_stages()) {
        SCOPED_TRACE("--" + option.name + " (" + GetParam() + ")");
        const RenderJob other = changed(job, option.name);
        const unsigned upstream = option.stages;

        // What re-runs: the session's counters across set_job.
        const auto before = session.stage_counters();
        session.set_job(other);
        session.prepare();
        const auto after = session.stage_counters();
        EXPECT_EQ(after.scene_builds - before.scene_builds, (upstream & stage_scene) ? 1 : 0);
        const bool photons_rerun = (upstream & (stage_scene | stage_photons)) != 0;
        // (The GI views declare the photon stage but all mean "a GI map": one to another keeps it.)
        const bool key_changed = option.cache_key(other.options) != option.cache_key(job.options);
        EXPECT_EQ(after.photon_passes - before.photon_passes,
                  photons_rerun && key_changed && caustics_needed(other) ? 1 : 0);
        const bool content = (upstream & (stage_scene | stage_photons | stage_image | stage_output)) != 0;
        EXPECT_EQ(job_content_fingerprint(other) != job_content_fingerprint(job), content);

        // What changes: nothing downstream of what it does not feed. The photons are built from
        // scratch; the image is rendered from the session's stages, which the photon check has
        // just shown to be the ones a fresh session builds.
        const bool compare = option.name != "reproducible";  // its change is to random streams
        if (!photons_rerun) {
            EXPECT_TRUE(same_photons(stage_photons_of(other), base_photons)) << "changes the photons undeclared";
        } else if (compare && !same_photons(stage_photons_of(other), base_photons)) {
            ++changed_photons;
        }
        if ((upstream & (stage_scene | stage_photons | stage_image)) == 0) {
            EXPECT_TRUE(same_pixels(rendered(session), base_image)) << "changes the image undeclared";
        } else if (other.width != job.width || other.height != job.height) {
            ++changed_images;  // a new size (not rendered: up to 1024 x 1024)
        } else if (compare && !same_pixels(rendered(session), base_image)) {
            ++changed_images;
        }
        session.set_job(job);  // back to the base: only what the option fed is built again
        session.prepare();
    }
    // The walk is not vacuous: most declarations do change what they feed in these jobs.
    EXPECT_GE(changed_photons, 8);
    EXPECT_GE(changed_images, 20);
}

INSTANTIATE_TEST_SUITE_P(Integrators, OptionWalk,
                         ::testing::Values("--integrator classic", "--integrator progressive --passes 9",
                                           "--integrator progressive --passes 9 --gi --gi-num-photons 5000"),
                         [](const auto& info) {
                             return std::string(info.index == 0 ? "classic" : info.index == 1 ? "progressive" : "progressive_gi");
                         });

}  // namespace
}  // namespace caustica
