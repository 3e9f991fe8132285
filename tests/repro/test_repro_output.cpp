// The reproducers of the hardening audit (tests/repro/README.md), part 4: where a scene's outputs
// land (W1). A gr.render name that leads out of the current folder through a symlink, as an archive
// restores one, is refused with the call's file:line and writes nothing; symlinks that stay inside,
// plain folders and -o still write (docs/RELIABILITY.md, section 1). Each test runs
// `caustica render` in a child (tests/repro/repro_runner.h) in a fresh folder.
#include "tests/repro/repro_runner.h"

#include <gtest/gtest.h>

using namespace caustica::repro;

namespace {

/// SCRATCH/download, the folder the user runs in, holding the reproducer's scene (rendering
/// `output` in place of its 'pics/holiday.png'), and SCRATCH/victim/holiday.png, another folder's file.
struct Download {
    Scratch s;
    fs::path victim = s.write("victim/holiday.png", "PRECIOUS-PHOTO");
    fs::path here = s.root() / "download";

    explicit Download(const std::string& output = "pics/holiday.png") {
        std::string scene = read_text(repro_source("output_symlinked_folder/scene.lua"));
        const std::string named = "pics/holiday.png";
        scene.replace(scene.find(named), named.size(), output);
        s.write("download/scene.lua", scene);
    }

    /// Appends a line to the scene.
    void add_line(const std::string& line) const {
        s.write("download/scene.lua", read_text(here / "scene.lua") + line + "\n");
    }

    /// `caustica render -s scene.lua ARGS` in download/.
    Outcome render(std::vector<std::string> args = {}) const {
        args.insert(args.begin(), {"render", "-s", "scene.lua"});
        return caustica_run(here, std::move(args), 10.0);
    }
};

/// Refused at scene.lua:`line` as leading outside, through `shown` to the victim's folder.
void expect_refused(const Outcome& o, const std::string& shown, int line) {
    expect_scene_error(o, "scene.lua", line);
    const std::string message =
        "scene.lua:" + std::to_string(line) + ": gr.render: output '" + shown + "' leads to '";
    EXPECT_NE(o.err.find(message), std::string::npos) << "expected '" << message << "'\n" << o.describe();
    EXPECT_NE(o.err.find("/victim/"), std::string::npos) << o.describe();
    EXPECT_NE(o.err.find("outside the current folder"), std::string::npos) << o.describe();
}

bool is_png(const fs::path& path) { return read_text(path).rfind("\x89PNG", 0) == 0; }

}  // namespace

TEST(ReproOutput, W1_FolderSymlinkLeadingOutIsRefused) {
    Download d;
    fs::create_directory_symlink(d.victim.parent_path(), d.here / "pics");
    const Tree before = snapshot(d.s.root());
    const Outcome o = d.render();
    expect_refused(o, "pics/holiday.png", 3);
    EXPECT_EQ(read_text(d.victim), "PRECIOUS-PHOTO");
    EXPECT_EQ(changes(before, snapshot(d.s.root())), std::vector<std::string>{}) << o.describe();
}

TEST(ReproOutput, W1_FileSymlinkLeadingOutIsRefused) {
    Download d("holiday.png");
    fs::create_symlink(d.victim, d.here / "holiday.png");
    const Tree before = snapshot(d.s.root());
    const Outcome o = d.render();
    expect_refused(o, "holiday.png", 3);
    EXPECT_EQ(read_text(d.victim), "PRECIOUS-PHOTO");
    EXPECT_TRUE(fs::is_symlink(d.here / "holiday.png"));
    EXPECT_EQ(changes(before, snapshot(d.s.root())), std::vector<std::string>{}) << o.describe();
}

TEST(ReproOutput, W1_EveryRenderAndEveryFrameIsCheckedBeforeAnyIsWritten) {
    {  // a second gr.render through the symlink: refused at its line, the first not written either
        Download d("first.png");
        d.add_line("gr.render(s, 'pics/holiday.png', 8, 8, {0,0,5}, {0,0,-1}, {0,1,0}, 50, {0.1,0.1,0.1}, {l})");
        fs::create_directory_symlink(d.victim.parent_path(), d.here / "pics");
        const Tree before = snapshot(d.s.root());
        const Outcome o = d.render();
        expect_refused(o, "pics/holiday.png", 4);
        EXPECT_EQ(changes(before, snapshot(d.s.root())), std::vector<std::string>{}) << o.describe();
    }
    {  // the frames of an animation (docs/ANIMATION.md) are named after the script's name
        Download d;
        fs::create_directory_symlink(d.victim.parent_path(), d.here / "pics");
        const Tree before = snapshot(d.s.root());
        const Outcome o = d.render({"--orbit-frames", "2"});
        expect_refused(o, "pics/holiday-0001.png", 3);
        EXPECT_EQ(changes(before, snapshot(d.s.root())), std::vector<std::string>{}) << o.describe();
    }
}

TEST(ReproOutput, W1_SymlinksThatStayInsideAndPlainFoldersStillWrite) {
    {  // pics -> real, a folder beside it
        Download d;
        fs::create_directory(d.here / "real");
        fs::create_directory_symlink("real", d.here / "pics");
        const Outcome o = d.render();
        EXPECT_EQ(o.exit_code, 0) << o.describe();
        EXPECT_TRUE(is_png(d.here / "real" / "holiday.png")) << o.describe();
    }
    {  // pics, a plain folder, with the frames of an animation
        Download d;
        fs::create_directory(d.here / "pics");
        const Outcome o = d.render({"--orbit-frames", "2"});
        EXPECT_EQ(o.exit_code, 0) << o.describe();
        EXPECT_TRUE(is_png(d.here / "pics" / "holiday-0001.png")) << o.describe();
        EXPECT_TRUE(is_png(d.here / "pics" / "holiday-0002.png")) << o.describe();
        EXPECT_EQ(read_text(d.victim), "PRECIOUS-PHOTO");
    }
}

TEST(ReproOutput, W1_OutputFlagIsTheUsersChoice) {
    Download d;
    fs::create_directory_symlink(d.victim.parent_path(), d.here / "pics");
    const Outcome o = d.render({"-o", "pics/mine.png"});
    EXPECT_EQ(o.exit_code, 0) << o.describe();
    EXPECT_TRUE(is_png(d.victim.parent_path() / "mine.png")) << o.describe();
    EXPECT_EQ(read_text(d.victim), "PRECIOUS-PHOTO");
}

TEST(ReproOutput, W1_AFolderSymlinkLoopIsRefusedNamingTheCall) {
    // The folder cannot be resolved at all: an error naming the gr.render's line (the folder is the
    // environment's: exit 1, as for a missing folder), not a bare file-system exception.
    Download d("loopa/x.png");
    fs::create_directory_symlink("loopb", d.here / "loopa");
    fs::create_directory_symlink("loopa", d.here / "loopb");
    const Tree before = snapshot(d.s.root());
    const Outcome o = d.render();
    EXPECT_EQ(o.exit_code, 1) << o.describe();
    EXPECT_NE(o.err.find("scene.lua:3: gr.render: cannot write 'loopa/x.png': folder 'loopa': "), std::string::npos)
        << o.describe();
    EXPECT_EQ(o.err.find("filesystem error"), std::string::npos) << o.describe();
    EXPECT_EQ(changes(before, snapshot(d.s.root())), std::vector<std::string>{}) << o.describe();
}
