// The integrator registry (core/integrators/registry.h): every entry is reachable by its name from
// the command line, and what it declares matches what it does.
#include "core/integrators/registry.h"
#include "core/scene/options.h"
#include "tests/scene_test_helpers.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace caustica {
namespace {

TEST(IntegratorRegistry, EveryEntryIsNamedOnceAndParsedByItsName) {
    std::set<std::string> names;
    for (const IntegratorEntry& entry : integrator_entries()) {
        EXPECT_TRUE(names.insert(entry.name).second) << entry.name << " twice";
        Options o;
        apply_option_tokens(o, {"--integrator", entry.name});
        EXPECT_EQ(o.integrator, entry.kind) << entry.name;
        EXPECT_EQ(&integrator_entry(entry.kind), &entry);
        EXPECT_EQ(find_integrator(entry.name), &entry);
        if (entry.kind != Options{}.integrator) {  // the options line of the metadata names it
            EXPECT_EQ(describe_non_default(o), std::string("--integrator ") + entry.name);
        }
    }
    EXPECT_EQ(find_integrator("pathtracer"), nullptr);
    EXPECT_EQ(integrator_entries().front().kind, Options{}.integrator) << "the default first";
}

TEST(IntegratorRegistry, EachEntryMakesWhatItDeclares) {
    const RenderJob base = testing::glass_and_mirror_balls_job("--caustic-num-photons 5000");
    for (const IntegratorEntry& entry : integrator_entries()) {
        SCOPED_TRACE(entry.name);
        RenderJob job = base;
        job.options.integrator = entry.kind;
        ShadingSetup setup;
        EXPECT_STREQ(entry.make(setup, job.options)->name(), entry.name);
        // An integrator that accumulates has a loop of its own; one that does not, the tile passes.
        EXPECT_EQ(entry.make_loop != nullptr, entry.accumulates);
        job.options.passes = 4;
        EXPECT_EQ(job.options.accumulates(), entry.accumulates);
        // Both want photons for the balls' caustics, and none without lights.
        EXPECT_TRUE(caustics_needed(job));
        RenderJob dark = job;
        dark.lights.clear();
        EXPECT_FALSE(caustics_needed(dark));
    }
}

}  // namespace
}  // namespace caustica
