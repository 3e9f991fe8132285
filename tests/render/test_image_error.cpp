// The caustic error (docs/ACCURACY.md, "The caustic error"): its region and figures on images
// whose answers are known by hand, and `caustica compare`, which prints them for two files.
#include "core/io/image_io.h"
#include "core/render/image_error.h"

#include "tests/run_command.h"
#include "tests/temp_folder.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace caustica;

namespace {

/// 100 pixels: 10 lit at 0.5 (grey), one at 4 (shows as 1), the rest black.
Image lit_reference() {
    Image image(10, 10);
    for (int i = 0; i < 10; ++i) image.pixels[static_cast<std::size_t>(i)] = glm::vec3(0.5f);
    image.pixels[50] = glm::vec3(4.0f);
    return image;
}

}  // namespace

TEST(CausticError, TheRegionIsATenthOfTheNinetyNinthPercentile) {
    Image reference = lit_reference();
    // 11 non-zero shown values: ten of 0.5 and one of 1; the 99th percentile is element
    // floor(0.99 x 10) = 9 of the sorted list, 0.5: the threshold is 0.05.
    reference.pixels[60] = glm::vec3(0.06f);  // above it: counted (13 values now, percentile still 0.5)
    reference.pixels[61] = glm::vec3(0.04f);  // below it: not
    const std::vector<std::size_t> region = caustic_region(reference);
    EXPECT_EQ(region.size(), 12u);
    EXPECT_NE(std::find(region.begin(), region.end(), 60u), region.end());
    EXPECT_EQ(std::find(region.begin(), region.end(), 61u), region.end());
    EXPECT_TRUE(caustic_region(Image(4, 4)).empty());
}

TEST(CausticError, FiguresOfAKnownDifference) {
    const Image reference = lit_reference();
    Image image = reference;
    image.pixels[0] = glm::vec3(0.7f);   // +0.2 on one pixel of the region
    image.pixels[50] = glm::vec3(9.0f);  // shows 1 like the reference's 4: no error
    const ImageError e = compare_images(image, reference, caustic_region(reference));
    EXPECT_EQ(e.region_pixels, 11u);
    // Region mean of the reference: (10 x 0.5 + 1) / 11; RMS difference: sqrt(0.2^2 / 11).
    const double mean = 6.0 / 11.0, rms = std::sqrt(0.04 / 11.0);
    EXPECT_NEAR(e.rel_rmse, rms / mean, 1e-6);
    EXPECT_NEAR(e.rel_bias, 0.2 / 6.0, 1e-6);
    EXPECT_NEAR(e.rmse, std::sqrt(0.04 / 100.0), 1e-6);
    EXPECT_EQ(compare_images(reference, reference, caustic_region(reference)).rel_rmse, 0.0);
}

class CompareCommand : public ::testing::Test {
protected:
    caustica::testing::CommandResult run(const std::string& args) const {
        return caustica::testing::run_shell("cd '" + dir_.path().string() + "' && '" CAUSTICA_BINARY "' compare " + args);
    }
    caustica::testing::TempFolder dir_{"caustica_compare"};
};

TEST_F(CompareCommand, PrintsTheCausticErrorOfTwoFiles) {
    const Image reference = lit_reference();
    Image image = reference;
    image.pixels[0] = glm::vec3(0.7f);
    write_pfm_atomic(dir_.file("reference.pfm"), reference);
    write_pfm_atomic(dir_.file("image.pfm"), image);
    const auto r = run("image.pfm reference.pfm");
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_NE(r.output.find("caustic region       11 pixels of 100"), std::string::npos) << r.output;
    char expected[64];
    std::snprintf(expected, sizeof expected, "relative RMSE        %.4f", std::sqrt(0.04 / 11.0) / (6.0 / 11.0));
    EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
}

TEST_F(CompareCommand, BadArgumentsAndFilesAreClearErrors) {
    write_pfm_atomic(dir_.file("reference.pfm"), lit_reference());
    write_pfm_atomic(dir_.file("small.pfm"), Image(4, 4));
    write_pfm_atomic(dir_.file("black.pfm"), Image(10, 10));
    Image broken = lit_reference();
    broken.pixels[23] = glm::vec3(0.0f, std::nanf(""), 0.0f);
    write_pfm_atomic(dir_.file("nan.pfm"), broken);
    struct Case {
        std::string args, says;
    } cases[] = {
        {"reference.pfm", "compare takes an image and a reference"},
        {"small.pfm reference.pfm", "small.pfm is 4 x 4, reference.pfm is 10 x 10"},
        {"reference.pfm black.pfm", "black.pfm: every pixel is black"},
        {"missing.pfm reference.pfm", "missing.pfm"},
        {"nan.pfm reference.pfm", "nan.pfm: pixel (3, 2) is not a finite number"},
    };
    for (const Case& c : cases) {
        const auto r = run(c.args);
        EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.says), std::string::npos) << c.args << "\n" << r.output;
    }
    EXPECT_EQ(run("--help").code, 0);
}
