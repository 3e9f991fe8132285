// Where a scene's outputs land (core/io/output_folder.h, docs/RELIABILITY.md section 1): a write
// confined to the current folder is judged on the real file system when it is made, so a folder or
// file symlink that leads out is refused, even one that appears after the check before rendering;
// symlinks that stay inside and plain folders are written; the user's own names are not confined.
#include "core/io/image_io.h"
#include "core/io/output_folder.h"
#include "tests/temp_folder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace caustica;
using caustica::testing::InFolder;
using caustica::testing::TempFolder;
namespace fs = std::filesystem;

namespace {

/// TEMP/work, the current folder of a run, and TEMP/victim/holiday.png, a file no scene may replace.
struct Layout {
    TempFolder temp;
    fs::path work = temp.path() / "work";
    fs::path victim = temp.write("victim/holiday.png", "PRECIOUS-PHOTO");

    Layout() { fs::create_directory(work); }
};

/// Writes a small image under a scene's name, as `caustica render` writes gr.render's names.
void write_scene_output(const std::string& name) {
    write_image_atomic(name, Image(4, 4), ImageWriteSettings{}, {}, nullptr, OutputPlace::inside_current_folder);
}

std::string text_of(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The names in `folder`, sorted (temporaries included).
std::vector<std::string> names_in(const fs::path& folder) {
    std::vector<std::string> names;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder)) names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

const std::vector<std::string> victim_alone = {"holiday.png"};

}  // namespace

TEST(OutputFolder, AFolderSymlinkLeadingOutIsRefusedAndTheUsersNameIsNot) {
    Layout l;
    fs::create_directory_symlink(l.victim.parent_path(), l.work / "pics");  // as an archive restores it
    const InFolder in(l.work);
    try {
        write_scene_output("pics/holiday.png");
        ADD_FAILURE() << "written through the symlink";
    } catch (const OutputOutsideFolder& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind("'pics/holiday.png' leads to '", 0), 0u) << message;
        EXPECT_NE(message.find("/victim/holiday.png', outside the current folder '"), std::string::npos) << message;
        EXPECT_EQ(output_outside_current_folder("pics/holiday.png"), message);  // the check before rendering agrees
    }
    EXPECT_EQ(text_of(l.victim), "PRECIOUS-PHOTO");
    EXPECT_EQ(names_in(l.victim.parent_path()), victim_alone);  // no temporary left there either
    // -o is the user's own choice: it goes where the user says.
    write_image_atomic("pics/mine.png", Image(4, 4), ImageWriteSettings{});
    EXPECT_TRUE(fs::is_regular_file(l.victim.parent_path() / "mine.png"));
}

TEST(OutputFolder, TheWriteChecksAgainAfterTheCheckBeforeRendering) {
    Layout l;
    fs::create_directory(l.work / "pics");
    const InFolder in(l.work);
    EXPECT_EQ(output_outside_current_folder("pics/holiday.png"), "");
    // The folder is swapped for a symlink leading out between the check and the write.
    fs::rename(l.work / "pics", l.work / "was_pics");
    fs::create_directory_symlink(l.victim.parent_path(), l.work / "pics");
    EXPECT_THROW(write_scene_output("pics/holiday.png"), OutputOutsideFolder);
    EXPECT_EQ(text_of(l.victim), "PRECIOUS-PHOTO");
    EXPECT_EQ(names_in(l.victim.parent_path()), victim_alone);
    EXPECT_TRUE(names_in(l.work / "was_pics").empty());
}

TEST(OutputFolder, AFileSymlinkLeadingOutIsRefused) {
    Layout l;
    fs::create_symlink(l.victim, l.work / "holiday.png");
    fs::create_directory(l.work / "sub");
    fs::create_symlink("../../victim/holiday.png", l.work / "sub" / "relative.png");
    const InFolder in(l.work);
    for (const char* name : {"holiday.png", "sub/relative.png"}) {
        EXPECT_NE(output_outside_current_folder(name).find("/victim/holiday.png', outside the current folder"),
                  std::string::npos)
            << name;
        EXPECT_THROW(write_scene_output(name), OutputOutsideFolder) << name;
    }
    EXPECT_EQ(text_of(l.victim), "PRECIOUS-PHOTO");
    EXPECT_EQ(names_in(l.victim.parent_path()), victim_alone);
    EXPECT_TRUE(fs::is_symlink(l.work / "holiday.png"));
    EXPECT_TRUE(fs::is_symlink(l.work / "sub" / "relative.png"));
}

TEST(OutputFolder, SymlinksThatStayInsideAndPlainFoldersAreWritten) {
    Layout l;
    fs::create_directories(l.work / "real" / "deeper");
    fs::create_directory(l.work / "plain");
    fs::create_directory_symlink("real", l.work / "pics");                            // relative, back inside
    fs::create_directory_symlink(l.work / "real" / "deeper", l.work / "plain" / "abs");  // absolute, inside
    const InFolder in(l.work);
    for (const char* name : {"top.png", "pics/a.png", "plain/b.png", "./plain/abs/c.png"}) {
        EXPECT_EQ(output_outside_current_folder(name), "") << name;
        EXPECT_NO_THROW(write_scene_output(name)) << name;
    }
    for (const char* written : {"top.png", "real/a.png", "plain/b.png", "real/deeper/c.png"})
        EXPECT_EQ(text_of(l.work / written).rfind("\x89PNG", 0), 0u) << written;
    EXPECT_EQ(names_in(l.victim.parent_path()), victim_alone);
}
