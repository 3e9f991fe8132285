// The option table: parsing, validation, suggestions, precedence.
#include "core/scene/options.h"
#include "core/scene/scene_desc.h"
#include "core/scene/source_location.h"

#include <gtest/gtest.h>

using namespace caustica;

namespace {

std::string error_of(const std::vector<std::string>& tokens) {
    Options o;
    try {
        apply_option_tokens(o, tokens);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(Options, DefaultsAreTheSeeds) {
    const Options o;
    EXPECT_EQ(o.aa_grid, 3);
    EXPECT_DOUBLE_EQ(o.aa_threshold, 0.5);
    EXPECT_EQ(o.caustic_num_photons, 0);
    EXPECT_EQ(o.caustic_num_neighbours, 5);  // --caustic-num-neighbours defaults to 5
    EXPECT_EQ(o.gi_num_photons, 1'000'000);  // --gi-num-photons 1 000 000
    EXPECT_EQ(o.gi_num_neighbours, 100);     // --gi-num-neighbours 100
    EXPECT_FALSE(o.gi_wanted());
    EXPECT_EQ(o.integrator, IntegratorKind::classic);  // the classic integrator is the default
    EXPECT_EQ(o.caustic_pm_gran, 180);
    EXPECT_EQ(o.shadow_grid, 4);
    EXPECT_DOUBLE_EQ(o.unit_distance, 1.0);
    EXPECT_DOUBLE_EQ(o.energy_fudge, 1.0);
    EXPECT_DOUBLE_EQ(o.effective_caustic_max_dist(), 0.15);
    EXPECT_EQ(o.projection_map, ProjectionMapMode::automatic);
}

TEST(Options, ParsesFlagsValuesAndShortForms) {
    Options o;
    apply_option_tokens(o, {"--a4", "-S", "-t", "--aa-grid", "5", "--aa-threshold=0.25", "-j", "2",
                            "--caustic-num-photons", "1e6", "--projection-map", "off", "--unit-distance", "2.5",
                            "--hires"});
    EXPECT_TRUE(o.a4);
    EXPECT_TRUE(o.stats);
    EXPECT_TRUE(o.timing);
    EXPECT_EQ(o.aa_grid, 5);
    EXPECT_DOUBLE_EQ(o.aa_threshold, 0.25);
    EXPECT_EQ(o.threads, 2);
    EXPECT_EQ(o.caustic_num_photons, 1000000);
    EXPECT_EQ(o.projection_map, ProjectionMapMode::off);
    EXPECT_DOUBLE_EQ(o.effective_caustic_max_dist(), 0.15 * 2.5);
    EXPECT_EQ(o.resolution_override, 1024);
}

TEST(Options, ShortOptionsTakeAttachedValuesAndBundle) {
    Options o;
    apply_option_tokens(o, {"-j2", "-St"});
    EXPECT_EQ(o.threads, 2);
    EXPECT_TRUE(o.stats);
    EXPECT_TRUE(o.timing);
    EXPECT_FALSE(o.silent);
    Options same;
    apply_option_tokens(same, {"-j", "2", "-S", "-t"});
    EXPECT_EQ(describe_non_default(o), describe_non_default(same));
    EXPECT_EQ(error_of({"-jx"}), "--threads: expected a whole number, got 'x'");
    EXPECT_EQ(error_of({"-j"}), "--threads: expects a value (N)");
    EXPECT_EQ(error_of({"-Sj2"}),
              "unknown option '-Sj2': '-j' is not a short flag (a short option taking a value goes alone or first, as in -j2)");
    EXPECT_EQ(error_of({"-Sq"}).rfind("unknown option '-Sq'", 0), 0u);
    EXPECT_EQ(error_of({"-x2"}), "unknown option '-x2'");
}

TEST(Options, OutputToneAndExrOptions) {
    const Options defaults;
    EXPECT_EQ(defaults.tonemap, Tonemap::clamp);
    EXPECT_EQ(defaults.exposure, 0.0);
    EXPECT_EQ(defaults.exr_pixel, ExrPixel::half);
    Options o;
    apply_option_tokens(o, split_option_string("--tonemap filmic --exposure -1.5 --exr-pixel float"));
    EXPECT_EQ(o.tonemap, Tonemap::filmic);
    EXPECT_EQ(o.exposure, -1.5);
    EXPECT_EQ(o.exr_pixel, ExrPixel::float32);
    EXPECT_EQ(describe_non_default(o), "--tonemap filmic --exposure -1.5 --exr-pixel float");
    apply_option_tokens(o, {"--tonemap=reinhard"});
    EXPECT_EQ(o.tonemap, Tonemap::reinhard);
    EXPECT_EQ(error_of({"--tonemap", "aces"}), "--tonemap: expected clamp, reinhard or filmic, got 'aces'");
    EXPECT_EQ(error_of({"--exposure", "100"}), "--exposure: 100 is out of range [-64, 64]");
    EXPECT_EQ(error_of({"--exr-pixel", "double"}), "--exr-pixel: expected half or float, got 'double'");
    const std::string help = options_help();
    for (const char* text : {"--tonemap clamp|reinhard|filmic", "--exposure D", "--exr-pixel half|float"})
        EXPECT_NE(help.find(text), std::string::npos) << text;
}

TEST(Options, UnknownOptionSuggestsTheClosest) {
    EXPECT_EQ(error_of({"--aa-gird", "3"}), "unknown option '--aa-gird' (did you mean --aa-grid?)");
    EXPECT_EQ(error_of({"--caustic-num-photon", "3"}),
              "unknown option '--caustic-num-photon' (did you mean --caustic-num-photons?)");
    EXPECT_EQ(error_of({"--zzzzzzzzzzzzzzzzzzzz"}), "unknown option '--zzzzzzzzzzzzzzzzzzzz'");
}

TEST(Options, BadValuesNameTheOption) {
    EXPECT_EQ(error_of({"--aa-grid", "-1"}), "--aa-grid: -1 is out of range [1, 16]");
    EXPECT_EQ(error_of({"--aa-grid", "three"}), "--aa-grid: expected a whole number, got 'three'");
    EXPECT_EQ(error_of({"--aa-grid"}), "--aa-grid: expects a value (N)");
    EXPECT_EQ(error_of({"--unit-distance", "0"}), "--unit-distance: 0 is out of range (0, 1e+30]");
    EXPECT_EQ(error_of({"--unit-distance", "nan"}), "--unit-distance: nan is not a finite number");
    EXPECT_EQ(error_of({"--unit-distance", "inf"}), "--unit-distance: inf is not a finite number");
    EXPECT_EQ(error_of({"--caustic-num-photons", "-5"}), "--caustic-num-photons: -5 is out of range [0, 100000000000]");
    EXPECT_EQ(error_of({"--projection-map", "maybe"}), "--projection-map: expected auto, on or off, got 'maybe'");
    EXPECT_EQ(error_of({"--a4=1"}), "--a4: takes no value");
    EXPECT_EQ(error_of({"scene.lua"}), "unexpected argument 'scene.lua' (options start with --)");
}

TEST(Options, GlobalIlluminationIsAcceptedNotIgnored) {
    // The --gi family is accepted: each token must reach the options, and each debug view turns the
    // GI map on.
    Options o;
    apply_option_tokens(o, {"--gi", "--gi-num-photons", "10", "--gi-num-neighbours", "7"});
    EXPECT_TRUE(o.gi);
    EXPECT_TRUE(o.gi_wanted());
    EXPECT_EQ(o.gi_num_photons, 10);
    EXPECT_EQ(o.gi_num_neighbours, 7);
    Options map_view;
    apply_option_tokens(map_view, {"--draw-gi-map"});
    EXPECT_TRUE(map_view.draw_gi_map);
    EXPECT_TRUE(map_view.gi_wanted());
    Options only_view;
    apply_option_tokens(only_view, {"--draw-gi-only"});
    EXPECT_TRUE(only_view.draw_gi_only);
    EXPECT_TRUE(only_view.gi_wanted());
    EXPECT_EQ(error_of({"--gi-num-neighbours", "0"}).find("--gi-num-neighbours"), 0u);  // still validated
}

TEST(Options, LaterTokensWinSoTheCommandLineCanOverrideTheScript) {
    Options o;
    apply_option_tokens(o, split_option_string("--aa-grid 2 --shadow-grid 7"));  // gr.option
    apply_option_tokens(o, {"--aa-grid", "6"});                                // command line
    EXPECT_EQ(o.aa_grid, 6);
    EXPECT_EQ(o.shadow_grid, 7);
}

TEST(Options, SplitsOptionStringsWithQuotes) {
    EXPECT_EQ(split_option_string("  --a4\t--threads 2 "), (std::vector<std::string>{"--a4", "--threads", "2"}));
    EXPECT_EQ(split_option_string("--x 'a b'"), (std::vector<std::string>{"--x", "a b"}));
    EXPECT_THROW(split_option_string("--x 'a b"), InputError);
}

TEST(Options, PositionalArgumentsAreCollectedWhenAllowed) {
    Options o;
    std::vector<std::string> positional;
    apply_option_tokens(o, {"--a4", "scene.lua", "-S"}, &positional);
    EXPECT_EQ(positional, std::vector<std::string>{"scene.lua"});
    EXPECT_TRUE(o.stats);
}

TEST(Options, DescribesOnlyNonDefaults) {
    Options o;
    EXPECT_EQ(describe_non_default(o), "");
    apply_option_tokens(o, {"--a4", "--aa-grid", "4"});
    EXPECT_EQ(describe_non_default(o), "--a4 --aa-grid 4");
}

TEST(Options, HelpListsEveryOptionOfTheSceneApi) {
    const std::string help = options_help();
    for (const char* name :
         {"--a4", "--timing", "--silent", "--stats", "--verbose", "--debug", "--disable-aa", "--disable-bv",
          "--disable-csg-bb", "--draw-aa", "--draw-caustic-map", "--draw-caustic-prm", "--draw-caustics-only",
          "--no-caustic-map", "--no-soft-shadows", "--reproducible", "--minres", "--lores", "--midres", "--hires",
          "--rays", "--gi", "--draw-gi-map", "--draw-gi-only", "--threads", "--aa-grid", "--aa-threshold",
          "--caustic-num-photons", "--caustic-num-neighbours", "--caustic-pm-gran", "--caustic-max-dist",
          "--projection-map", "--shadow-grid", "--unit-distance", "--energy-fudge", "--gi-num-photons",
          "--gi-num-neighbours", "--script-timeout"})
        EXPECT_NE(help.find(name), std::string::npos) << name;
}

TEST(Options, EditDistance) {
    EXPECT_EQ(edit_distance("kitten", "sitting"), 3);
    EXPECT_EQ(edit_distance("", "abc"), 3);
    EXPECT_EQ(edit_distance("same", "same"), 0);
}

TEST(Options, CommandLineTakesTheScriptOriginOfWhatItSetsInAnyForm) {
    // Errors about an option's value name the gr.option line only while the script set it.
    RenderJob job;
    const SourceLocation where{"scene.lua", 3};
    job.option_origins = {{"threads", where}, {"silent", where}, {"stats", where}, {"timing", where},
                          {"caustic-num-photons", where}};
    job.apply_command_line({"-j2", "-St", "--caustic-num-photons=5"});
    EXPECT_EQ(job.options.threads, 2);
    EXPECT_TRUE(job.options.stats);
    EXPECT_TRUE(job.options.timing);
    EXPECT_EQ(job.option_origin("threads"), nullptr);
    EXPECT_EQ(job.option_origin("stats"), nullptr);
    EXPECT_EQ(job.option_origin("timing"), nullptr);
    EXPECT_EQ(job.option_origin("caustic-num-photons"), nullptr);
    ASSERT_NE(job.option_origin("silent"), nullptr);  // not on the command line: still the script's
    EXPECT_EQ(job.option_origin("silent")->line, 3);
}

// --time or --target-error alone mean "until that rule"; --passes, when given, still limits.
TEST(Options, TimeOrTargetErrorAloneLiftThePassLimit) {
    Options o;
    EXPECT_EQ(o.pass_limit(), 1);
    apply_option_tokens(o, {"--integrator", "progressive", "--time", "60"});
    EXPECT_EQ(o.pass_limit(), 0);
    EXPECT_TRUE(o.accumulates());
    EXPECT_EQ(describe_non_default(o), "--integrator progressive --time 60");
    Options target;
    apply_option_tokens(target, {"--target-error", "0.05"});
    EXPECT_EQ(target.pass_limit(), 0);
    Options both;
    apply_option_tokens(both, {"--time", "60", "--passes", "1"});
    EXPECT_EQ(both.pass_limit(), 1);  // given: one accumulating pass within the time
    EXPECT_EQ(describe_non_default(both), "--passes 1 --time 60");  // told, so it means the same again
    Options explicit_none;
    apply_option_tokens(explicit_none, {"--passes", "0", "--time", "5"});
    EXPECT_EQ(explicit_none.pass_limit(), 0);
    Options many;
    apply_option_tokens(many, {"--passes", "16", "--target-error", "0.1"});
    EXPECT_EQ(many.pass_limit(), 16);
}
