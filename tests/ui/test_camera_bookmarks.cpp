// Camera bookmarks (docs/PREVIEW.md, "What you see is what you save"): the file round trips,
// unreadable lines and hand edits survive a save, two previews changing the file at once lose
// nothing (the lock), the writer stays within its limit, and a file over the read limit or not a
// regular file is never written over.
#include "ui/camera_bookmarks.h"
#include "ui_test_support.h"

#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <set>
#include <thread>

namespace caustica::ui {
namespace {

using namespace caustica::ui::testing;
using caustica::testing::time_bound;

/// A camera every bookmark of these tests may share.
CameraDesc front_camera() {
    CameraDesc c;
    c.eye = {1.0, 2.0, 3.0};
    c.view = {0.0, 0.0, -1.0};
    c.fovy_degrees = 45.0;
    return c;
}

/// The warning for a bookmarks file over the read limit.
std::string read_only_start(const std::string& file) {
    return file + ": larger than 1 MiB; only the bookmarks in its first 1 MiB are read, and it is never written over "
                  "(remove old lines by hand to save new ones)";
}

using NamesAndEyes = std::vector<std::pair<std::string, glm::dvec3>>;

/// The names and eye points of the bookmarks of `scene`, in order.
NamesAndEyes names_and_eyes(const CameraBookmarks& marks, const std::string& scene) {
    NamesAndEyes found;
    for (const auto& [name, camera] : marks.of(scene)) found.emplace_back(name, camera.eye);
    return found;
}

/// Runs `work` in a child process, which exits 0 when it returns true.
pid_t start_child(const std::function<bool()>& work) {
    const pid_t child = ::fork();
    if (child == 0) {
        bool ok = false;
        try {
            ok = work();
        } catch (...) {
        }
        ::_exit(ok ? 0 : 1);
    }
    return child;
}

/// The exit code of `child`, or -1 when a signal ended it (SIGKILL from here once `seconds` passed).
int exit_code_within(pid_t child, double seconds) {
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    int status = 0;
    while (::waitpid(child, &status, WNOHANG) == 0) {
        if (std::chrono::steady_clock::now() > give_up) {
            ::kill(child, SIGKILL);
            ::waitpid(child, &status, 0);
            return -1;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(Bookmarks, BookmarksPersistAndACorruptFileIsIgnoredWithAWarning) {
    TempFolder folder;
    const std::string file = folder.file("camera-bookmarks");
    CameraDesc a;
    a.eye = {1.0 / 3.0, 2.0, 3.0};
    a.view = {0.0, 0.0, -1.0};
    a.fovy_degrees = 45.0;
    CameraDesc b = a;
    b.eye.x = -7.25;
    {
        CameraBookmarks marks(file);
        EXPECT_TRUE(marks.set("/s/one.lua", "front", a));
        EXPECT_TRUE(marks.set("/s/one.lua", "side\tview", b));  // a tab would break the line format
        EXPECT_TRUE(marks.set("/s/two.lua", "front", b));
        EXPECT_FALSE(marks.set("/s/two.lua", "  ", b));
        EXPECT_TRUE(marks.set("/s/one.lua", "front", b));  // replaces
        marks.remove("/s/two.lua", "front");
        EXPECT_EQ(marks.warning(), "");
    }
    EXPECT_FALSE(fs::exists(file + ".tmp"));
    {
        CameraBookmarks marks(file);
        EXPECT_EQ(names_and_eyes(marks, "/s/one.lua"), (NamesAndEyes{{"front", b.eye}, {"side view", b.eye}}));
        EXPECT_TRUE(marks.of("/s/two.lua").empty());
        EXPECT_EQ(marks.warning(), "");
    }
    {  // exactly the bits written
        std::ofstream out(file, std::ios::app);
        out << "/s/one.lua\tbad\t1 2 3 0 0 0 0 1 0 45\n"       // no view direction
            << "garbage without tabs\n"
            << "/s/one.lua\tnan\t1 2 nan 0 0 -1 0 1 0 45\n"
            << "/s/one.lua\tok\t1 2 3 0 0 -1 0 1 0 30\n";
    }
    CameraBookmarks marks(file);
    EXPECT_EQ(marks.of("/s/one.lua").size(), 3u);
    EXPECT_EQ(marks.warning(), file + ": 3 unreadable lines ignored (kept in the file as they are; first: line 3)");
    {
        std::ofstream out(file, std::ios::trunc);
        out << std::string((1 << 20) + 1, 'x');
    }
    CameraBookmarks huge(file);
    EXPECT_TRUE(huge.of("/s/one.lua").empty());
    EXPECT_EQ(huge.warning(), read_only_start(file));
}

TEST(Bookmarks, BookmarksOfTwoPreviewsHandEditsAndOddScenePathsSurviveASave) {
    TempFolder folder;
    const std::string file = folder.file("camera-bookmarks");
    CameraDesc a;
    a.eye = {1.0, 2.0, 3.0};
    a.view = {0.0, 0.0, -1.0};
    CameraDesc b = a;
    b.eye.x = -4.5;
    const std::string hand_edit = "/s/one.lua\thand\t1 2 3 0 0 -1 0 1 0 45 extra";
    {
        std::ofstream out(file);
        out << "/s/one.lua\tfront\t1 2 3 0 0 -1 0 1 0 45\n" << hand_edit << "\n";
    }
    // Two windows opened before either saved: each keeps the other's bookmark.
    CameraBookmarks first(file), second(file);
    EXPECT_TRUE(first.set("/s/one.lua", "from first", a));
    EXPECT_TRUE(second.set("/s/one.lua", "from second", b));
    second.remove("/s/one.lua", "front");
    const std::string odd = "/s/we\nird\tname\\x.lua";  // line break, tab and backslash in a path
    EXPECT_TRUE(first.set(odd, "v", b));
    EXPECT_EQ(first.warning(), file + ": 1 unreadable line ignored (kept in the file as it is; first: line 1)");  // "front" removed above it
    CameraBookmarks again(file);
    EXPECT_EQ(names_and_eyes(again, "/s/one.lua"), (NamesAndEyes{{"from first", a.eye}, {"from second", b.eye}}));
    EXPECT_EQ(names_and_eyes(again, odd), (NamesAndEyes{{"v", b.eye}}));
    const std::string text = file_text(file);
    EXPECT_NE(text.find(hand_edit + "\n"), std::string::npos) << text;  // verbatim, in its place
    EXPECT_NE(text.find("\n/s/we\\nird\\tname\\\\x.lua\tv\t-4.5 2 3 0 0 -1 0 1 0 "), std::string::npos) << text;
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 4);
    // No temporary left; the lock file stays (removed, two previews could lock two different files).
    EXPECT_EQ(files_in(folder.path()), (std::vector<std::string>{"camera-bookmarks", "camera-bookmarks.lock"}));
}

TEST(Bookmarks, ABookmarksFileThatWasNotReadWholeIsNeverWrittenOver) {
    TempFolder folder;
    CameraDesc a;
    a.eye = {1.0, 2.0, 3.0};
    a.view = {0.0, 0.0, -1.0};
    const std::string big = folder.file("big");
    const std::string contents = std::string((1 << 20) + 1, 'x');
    {
        std::ofstream out(big);
        out << contents;
    }
    CameraBookmarks marks(big);
    EXPECT_EQ(marks.warning(), read_only_start(big));
    EXPECT_TRUE(marks.set("/s/a.lua", "front", a));
    EXPECT_EQ(marks.of("/s/a.lua").size(), 1u);  // kept for the session
    EXPECT_EQ(marks.warning(), read_only_start(big) + "; this change lasts until the preview closes");
    EXPECT_EQ(file_text(big), contents);

    const std::string fifo = folder.file("fifo");
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    CameraBookmarks piped(fifo);  // returns at once: no writer is waited for
    EXPECT_EQ(piped.warning(), fifo + ": is a named pipe (FIFO), not a regular file; camera bookmarks ignored");
    EXPECT_TRUE(piped.set("/s/a.lua", "front", a));
    EXPECT_TRUE(fs::is_fifo(fifo));
    EXPECT_EQ(files_in(folder.path()), (std::vector<std::string>{"big", "big.lock", "fifo", "fifo.lock"}));
}

TEST(Bookmarks, TwoPreviewsAddingAtOnceKeepEveryBookmark) {
    TempFolder folder;
    const std::string file = folder.file("camera-bookmarks");
    const int each = 200;
    const double lock_wait = time_bound(bookmarks_lock_wait_seconds);  // measured here, not in each child
    // Each process is one preview adding its bookmarks one by one, as fast as it can.
    auto add = [&](const std::string& who) {
        CameraBookmarks marks(file, lock_wait);
        for (int i = 0; i < each; ++i) {
            if (!marks.set("/s/shared.lua", who + " " + std::to_string(i), front_camera()) || !marks.warning().empty()) {
                std::fprintf(stderr, "%s %d: %s\n", who.c_str(), i, marks.warning().c_str());
                return false;
            }
        }
        return true;
    };
    const pid_t first = start_child([&] { return add("first"); });
    const pid_t second = start_child([&] { return add("second"); });
    ASSERT_GT(first, 0);
    ASSERT_GT(second, 0);
    EXPECT_EQ(exit_code_within(first, time_bound(20.0)), 0);
    EXPECT_EQ(exit_code_within(second, time_bound(20.0)), 0);

    CameraBookmarks after(file);
    EXPECT_EQ(after.warning(), "");
    std::set<std::string> names;
    for (const auto& [name, camera] : after.of("/s/shared.lua")) names.insert(name);
    std::set<std::string> expected;
    for (int i = 0; i < each; ++i) expected.insert({"first " + std::to_string(i), "second " + std::to_string(i)});
    EXPECT_EQ(names.size(), 2u * each);
    EXPECT_EQ(names, expected);
    EXPECT_EQ(files_in(folder.path()), (std::vector<std::string>{"camera-bookmarks", "camera-bookmarks.lock"}));
}

TEST(Bookmarks, AChangeWaitsABoundedTimeForTheLockAndSaysSoWhenItIsNotHad) {
    TempFolder folder;
    const std::string file = folder.file("camera-bookmarks");
    // Another preview in the middle of its change (or stopped there).
    const int held = ::open((file + ".lock").c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    ASSERT_GE(held, 0);
    ASSERT_EQ(::flock(held, LOCK_EX), 0);
    CameraBookmarks marks(file, 0.2);
    const auto start = std::chrono::steady_clock::now();
    EXPECT_FALSE(marks.set("/s/a.lua", "front", front_camera()));
    const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_GE(waited, 0.2);
    EXPECT_LT(waited, time_bound(1.0));
    EXPECT_EQ(marks.warning(),
              file + ".lock: still held by another process after 0.2 s; the camera bookmarks were not changed (try again)");
    EXPECT_TRUE(marks.of("/s/a.lua").empty());
    EXPECT_FALSE(fs::exists(file));

    ::close(held);  // the other preview is done: the same change now goes through
    EXPECT_TRUE(marks.set("/s/a.lua", "front", front_camera()));
    EXPECT_EQ(marks.warning(), "");
    EXPECT_EQ(CameraBookmarks(file).of("/s/a.lua").size(), 1u);
}

TEST(Bookmarks, TheWriterKeepsTheFileWithinItsLimitDroppingTheOldest) {
    TempFolder folder;
    const std::string file = folder.file("camera-bookmarks");
    // Long lines make the limit come soon (the limit is on bytes, whatever makes them).
    const std::string scene = "/s/" + std::string(24000, 'a') + ".lua";
    const int added = 80;  // about 1.9 MB of lines
    auto name = [](int i) {  // one length for all, so that the kept ones are exactly the newest
        char text[32];
        std::snprintf(text, sizeof text, "view %03d", i);
        return std::string(text);
    };
    CameraBookmarks marks(file);
    for (int i = 0; i < added; ++i) {
        ASSERT_TRUE(marks.set(scene, name(i), front_camera()));
        ASSERT_LE(fs::file_size(file), bookmarks_write_limit) << "after bookmark " << i;
    }
    static_assert(bookmarks_write_limit <= bookmarks_read_limit / 2);
    EXPECT_EQ(marks.warning(), file + ": 1 line dropped to keep the file within 512 KiB (the oldest go first)");

    const std::size_t line_bytes = file_text(file).find('\n') + 1;
    const std::size_t fit = bookmarks_write_limit / line_bytes;
    ASSERT_LT(fit, std::size_t(added));
    CameraBookmarks again(file);
    EXPECT_EQ(again.warning(), "");
    const auto kept = again.of(scene);
    ASSERT_EQ(kept.size(), fit);
    for (std::size_t k = 0; k < fit; ++k) EXPECT_EQ(kept[k].first, name(int(added - fit + k)));
    EXPECT_EQ(marks.of(scene).size(), fit);  // the window shows what was kept
}

TEST(Bookmarks, AFileOverTheReadLimitIsReadAsFarAsItGoesAndNeverWrittenOver) {
    TempFolder folder;
    const std::string file = folder.file("camera-bookmarks");
    // As an unbounded writer could leave it: about 27 000 bookmarks, 1.1 MiB.
    std::string contents;
    for (int i = 0; contents.size() <= bookmarks_read_limit + 100000; ++i)
        contents += "/s/a.lua\tview " + std::to_string(i) + "\t1 2 3 0 0 -1 0 1 0 45\n";
    folder.write("camera-bookmarks", contents);
    ASSERT_NE(contents[bookmarks_read_limit - 1], '\n');  // the limit cuts a line
    const auto whole_lines = std::size_t(std::count(contents.begin(), contents.begin() + bookmarks_read_limit, '\n'));

    CameraBookmarks marks(file);
    EXPECT_EQ(marks.warning(), read_only_start(file));
    const auto shown = marks.of("/s/a.lua");
    ASSERT_EQ(shown.size(), whole_lines);  // not the line cut at the limit
    EXPECT_EQ(shown.front().first, "view 0");
    EXPECT_EQ(shown.back().first, "view " + std::to_string(whole_lines - 1));

    EXPECT_TRUE(marks.set("/s/a.lua", "new", front_camera()));
    marks.remove("/s/a.lua", "view 0");
    EXPECT_EQ(marks.warning(), read_only_start(file) + "; this change lasts until the preview closes");
    EXPECT_EQ(marks.of("/s/a.lua").size(), whole_lines);  // one added, one removed, for this session
    EXPECT_EQ(file_text(file), contents);                 // not one bookmark of the file lost
    EXPECT_EQ(CameraBookmarks(file).of("/s/a.lua").size(), whole_lines);
}

}  // namespace
}  // namespace caustica::ui
