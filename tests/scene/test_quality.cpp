// --quality presets (docs/ACCURACY.md): each sets what the document says, a preset stands for its
// tokens at its place in the order (earlier options are replaced, later ones win), and it works
// from a scene's gr.option as from the command line.
#include "core/lua/scene_loader.h"
#include "core/scene/options.h"
#include "core/scene/source_location.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace caustica;

namespace {

/// What docs/ACCURACY.md promises for one preset.
struct Expected {
    const char* name;
    long long photons;
    int neighbours;
    int aa_grid;
    double aa_threshold;
    int shadow_grid;
};

constexpr Expected presets[] = {
    {"draft", 1'000'000, 25, 1, 0.5, 2},
    {"preview", 10'000'000, 25, 2, 0.5, 3},
    {"final", 30'000'000, 50, 4, 0.25, 6},
};

Options with(const std::vector<std::string>& tokens) {
    Options o;
    apply_option_tokens(o, tokens);
    return o;
}

}  // namespace

TEST(Quality, EachPresetSetsTheDocumentedValues) {
    for (const Expected& e : presets) {
        SCOPED_TRACE(e.name);
        const Options o = with({"--quality", e.name});
        EXPECT_EQ(o.caustic_num_photons, e.photons);
        EXPECT_EQ(o.caustic_num_neighbours, e.neighbours);
        EXPECT_DOUBLE_EQ(o.effective_caustic_max_dist(), 0.15);  // the default, 0.15 x unit distance
        EXPECT_EQ(o.aa_grid, e.aa_grid);
        EXPECT_DOUBLE_EQ(o.aa_threshold, e.aa_threshold);
        EXPECT_EQ(o.shadow_grid, e.shadow_grid);
        // Nothing else moves: the preset only touches the six values above.
        Options rest = o;
        const Options defaults;
        rest.caustic_num_photons = defaults.caustic_num_photons;
        rest.caustic_num_neighbours = defaults.caustic_num_neighbours;
        rest.aa_grid = defaults.aa_grid;
        rest.aa_threshold = defaults.aa_threshold;
        rest.shadow_grid = defaults.shadow_grid;
        EXPECT_EQ(describe_non_default(rest), "");
    }
}

TEST(Quality, PresetsGrowInCostFromDraftToFinal) {
    const Options draft = with({"--quality", "draft"}), preview = with({"--quality", "preview"}),
                  final = with({"--quality", "final"});
    EXPECT_LT(draft.caustic_num_photons, preview.caustic_num_photons);
    EXPECT_LT(preview.caustic_num_photons, final.caustic_num_photons);
    EXPECT_LE(draft.aa_grid, preview.aa_grid);
    EXPECT_LE(preview.aa_grid, final.aa_grid);
    EXPECT_LE(draft.shadow_grid, preview.shadow_grid);
    EXPECT_LE(preview.shadow_grid, final.shadow_grid);
}

TEST(Quality, LaterOptionsOverrideThePreset) {
    const Options o = with({"--quality", "final", "--caustic-num-neighbours", "42", "--aa-grid=2",
                            "--caustic-max-dist", "0.3"});
    EXPECT_EQ(o.caustic_num_neighbours, 42);
    EXPECT_EQ(o.aa_grid, 2);
    EXPECT_DOUBLE_EQ(o.effective_caustic_max_dist(), 0.3);
    EXPECT_EQ(o.caustic_num_photons, 30'000'000);  // the rest of the preset stays
    EXPECT_EQ(o.shadow_grid, 6);
    // A second preset replaces the first entirely.
    const Options twice = with({"--quality", "final", "--quality", "draft"});
    EXPECT_EQ(twice.caustic_num_photons, 1'000'000);
    EXPECT_EQ(twice.aa_grid, 1);
}

TEST(Quality, ThePresetReplacesEarlierOptions) {
    const Options o = with({"--caustic-num-photons", "5", "--caustic-max-dist", "0.4", "--shadow-grid", "9",
                            "--quality", "preview"});
    EXPECT_EQ(o.caustic_num_photons, 10'000'000);
    EXPECT_EQ(o.shadow_grid, 3);
    EXPECT_LT(o.caustic_max_dist, 0.0);  // back to "0.15 x unit distance"
}

TEST(Quality, MaximumDistanceFollowsTheUnitDistanceSetInAnyOrder) {
    EXPECT_DOUBLE_EQ(with({"--quality", "draft", "--unit-distance", "10"}).effective_caustic_max_dist(), 1.5);
    EXPECT_DOUBLE_EQ(with({"--unit-distance", "10", "--quality", "draft"}).effective_caustic_max_dist(), 1.5);
}

TEST(Quality, UnknownPresetNamesTheOptionAndTheChoices) {
    Options o;
    try {
        apply_option_tokens(o, {"--quality", "ultra"});
        FAIL() << "no error";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("--quality"), std::string::npos) << message;
        EXPECT_NE(message.find("draft, preview or final"), std::string::npos) << message;
        EXPECT_NE(message.find("ultra"), std::string::npos) << message;
    }
    EXPECT_THROW(apply_option_tokens(o, {"--quality"}), InputError);  // a value is required
}

TEST(Quality, HelpAndMetadataNameThePreset) {
    EXPECT_NE(options_help().find("--quality draft|preview|final"), std::string::npos);
    EXPECT_EQ(describe_non_default(Options{}).find("--quality"), std::string::npos);
    const std::string described = describe_non_default(with({"--quality", "preview"}));
    EXPECT_NE(described.find("--quality preview"), std::string::npos) << described;
    // Once a value is changed after it, the options no longer are the preset.
    const std::string changed = describe_non_default(with({"--quality", "preview", "--aa-grid", "5"}));
    EXPECT_EQ(changed.find("--quality"), std::string::npos) << changed;
    // Re-applying the description gives the same options (the PNG metadata can be replayed).
    const Options replayed = with(split_option_string(described));
    EXPECT_EQ(describe_non_default(replayed), described);
}

TEST(Quality, WorksFromTheSceneAndTheCommandLineStillWins) {
    namespace fs = std::filesystem;
    const fs::path script = fs::temp_directory_path() / ("caustica_quality_" + std::to_string(::getpid()) + ".lua");
    std::ofstream(script) << "gr.option('--quality draft --caustic-num-neighbours 7')\n"
                             "s = gr.node('s')\n"
                             "gr.render(s, 'out.png', 8, 8, {0,0,1}, {0,0,-1}, {0,1,0}, 50, {0,0,0}, {})\n";
    const SceneScript loaded = load_scene_script(script.string());
    fs::remove(script);
    ASSERT_EQ(loaded.renders.size(), 1u);
    Options o = loaded.renders[0].options;
    EXPECT_EQ(o.caustic_num_photons, 1'000'000);
    EXPECT_EQ(o.caustic_num_neighbours, 7);
    apply_option_tokens(o, {"--quality", "final"});  // what `caustica render --quality final` re-applies
    EXPECT_EQ(o.caustic_num_photons, 30'000'000);
    EXPECT_EQ(o.caustic_num_neighbours, 50);
}
