// The key queue of ui/key_events.h: a press reaches exactly the next frame, even when the key was
// released before that frame began (ImGui 1.86's IsKeyPressed loses such a tap). And the frame
// loop's wait of ui/frame_pacing.h, which shows the coarse preview of a new view as soon as the
// renderer has it (both are the platform side of the preview's frame loop).
#include "ui/frame_pacing.h"
#include "ui/key_events.h"
#include "ui/keys.h"
#include "ui/shortcuts.h"
#include "ui/view_arguments.h"
#include "ui_test_support.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

namespace caustica::ui {
namespace {

TEST(KeyEvents, ATapWithinOneFrameIsSeenExactlyOnce) {
    KeyEvents events;
    events.begin_frame();
    EXPECT_FALSE(events.pressed(keys::r));
    events.press(keys::r);  // pressed and released between two frames: only the press is recorded
    EXPECT_FALSE(events.pressed(keys::r)) << "a press belongs to the frame after it, not the current one";
    events.begin_frame();
    EXPECT_TRUE(events.pressed(keys::r));
    EXPECT_TRUE(events.pressed(keys::r)) << "asking twice within a frame does not use the press up";
    EXPECT_EQ(events.count(keys::r), 1);
    EXPECT_FALSE(events.pressed(keys::o));
    events.begin_frame();
    EXPECT_FALSE(events.pressed(keys::r)) << "a press is seen in one frame only";
    EXPECT_EQ(events.count(keys::r), 0);
}

TEST(KeyEvents, TwoTapsWithinOneFrameCountTwice) {
    KeyEvents events;
    events.press(keys::left);
    events.press(keys::right);
    events.press(keys::left);
    events.begin_frame();
    EXPECT_EQ(events.count(keys::left), 2);
    EXPECT_EQ(events.count(keys::right), 1);
    ASSERT_EQ(events.frame_presses().size(), 3u);
    EXPECT_EQ(events.frame_presses()[1].key, keys::right);  // in the order they happened
}

TEST(KeyEvents, AutoRepeatsCountOnlyWhenAskedFor) {
    KeyEvents events;
    events.press(keys::up, 0, true);
    events.press(keys::up, 0, true);
    events.begin_frame();
    EXPECT_FALSE(events.pressed(keys::up));
    EXPECT_TRUE(events.pressed(keys::up, true));
    EXPECT_EQ(events.count(keys::up, true), 2);
    events.press(keys::up);  // the first press, then its repeats
    events.press(keys::up, 0, true);
    events.begin_frame();
    EXPECT_EQ(events.count(keys::up), 1);
    EXPECT_EQ(events.count(keys::up, true), 2);
}

TEST(KeyEvents, ModifiersAreThoseHeldAtThePress) {
    KeyEvents events;
    events.press(keys::z, key_mods::ctrl | key_mods::shift | 0x10);  // 0x10: GLFW's Caps Lock, ignored
    events.press(keys::y, key_mods::ctrl);
    events.begin_frame();
    EXPECT_TRUE(events.pressed(keys::z)) << "pressed() ignores modifiers, as ImGui::IsKeyPressed";
    EXPECT_TRUE(events.pressed_with(keys::z, key_mods::ctrl | key_mods::shift));
    EXPECT_FALSE(events.pressed_with(keys::z, key_mods::ctrl)) << "Ctrl+Shift+Z is not Ctrl+Z";
    EXPECT_FALSE(events.pressed_with(keys::z, 0));
    EXPECT_TRUE(events.pressed_with(keys::y, key_mods::ctrl));
    EXPECT_FALSE(events.pressed_with(keys::y, key_mods::ctrl | key_mods::alt));
    EXPECT_EQ(events.frame_presses()[0].mods, key_mods::ctrl | key_mods::shift);
}

TEST(KeyEvents, PendingPressesAreBoundedAndClearForgetsThem) {
    KeyEvents events;
    for (int i = 0; i < 1000; ++i) events.press(keys::e);
    events.begin_frame();
    EXPECT_EQ(events.count(keys::e), static_cast<int>(KeyEvents::max_pending));
    events.press(keys::g);
    events.clear();
    EXPECT_FALSE(events.pressed(keys::e));
    events.begin_frame();
    EXPECT_FALSE(events.pressed(keys::g));
}

TEST(KeyEvents, ATapIsShownDownForOneFrameAndThenLifted) {
    KeyEvents events;
    events.press(keys::enter);
    events.release(keys::enter);  // released before the frame: ImGui's io.KeysDown never saw it
    events.press(keys::escape);   // still held when the frame begins: io.KeysDown shows it anyway
    events.begin_frame();
    EXPECT_EQ(events.taps(), std::vector<int>{keys::enter});
    EXPECT_TRUE(events.lifts().empty());
    events.release(keys::escape);  // released after the frame began: not a tap
    events.begin_frame();
    EXPECT_TRUE(events.taps().empty());
    EXPECT_EQ(events.lifts(), std::vector<int>{keys::enter});
    events.begin_frame();
    EXPECT_TRUE(events.lifts().empty());
    events.press(keys::up);
    events.press(keys::up, 0, true);  // auto-repeats do not make a second tap
    events.release(keys::up);
    events.press(keys::up);
    events.release(keys::up);
    events.begin_frame();
    EXPECT_EQ(events.taps(), std::vector<int>{keys::up});
    EXPECT_EQ(events.count(keys::up), 2) << "but both presses count";
}

TEST(KeyEvents, TheProcessQueueAnswersKeyPressed) {
    KeyEvents& events = key_events();
    events.clear();
    events.press(keys::s, key_mods::ctrl);
    events.begin_frame();
    EXPECT_TRUE(key_pressed(keys::s));
    EXPECT_TRUE(key_pressed_with(keys::s, key_mods::ctrl));
    EXPECT_FALSE(key_pressed_with(keys::s, 0));
    EXPECT_FALSE(key_pressed(keys::q));
    events.begin_frame();
    EXPECT_FALSE(key_pressed(keys::s));
    events.clear();
}

/// The actions one press asks for, with nothing else pressed.
std::vector<Shortcut> actions_of(int key, int mods, bool keyboard_taken = false) {
    KeyEvents events;
    events.press(key, mods);
    events.begin_frame();
    return shortcuts_pressed(events, keyboard_taken);
}

TEST(Shortcuts, TypingNeverActs) {
    // Letters, digits and signs typed after a missed click, with or without Shift: nothing.
    std::vector<int> typed = {keys::minus, keys::equal, keys::keypad_add, keys::keypad_subtract};
    for (int key = 'A'; key <= 'Z'; ++key) typed.push_back(key);
    for (int key = '0'; key <= '9'; ++key) typed.push_back(key);
    for (int key : typed)
        for (int mods : {0, key_mods::shift}) {
            EXPECT_TRUE(types_text(key, mods)) << key;
            EXPECT_TRUE(actions_of(key, mods).empty()) << "key " << key << " mods " << mods;
        }
}

TEST(Shortcuts, EveryShortcutTakesCtrlOrAltOrTypesNothingButThePause) {
    for (const ShortcutBinding& b : shortcut_bindings()) {
        if (b.action == Shortcut::pause) continue;  // Space: a pause loses nothing
        EXPECT_FALSE(types_text(b.key, b.mods)) << "key " << b.key << " mods " << b.mods;
        if (b.shift_too) {
            EXPECT_FALSE(types_text(b.key, b.mods | key_mods::shift)) << "key " << b.key;
        }
    }
    EXPECT_FALSE(types_text(keys::f5, 0));
    EXPECT_FALSE(types_text(keys::r, key_mods::ctrl));
    EXPECT_FALSE(types_text(keys::o, key_mods::alt));
}

TEST(Shortcuts, ModifiedLettersAndKeysThatTypeNothingAct) {
    using V = std::vector<Shortcut>;
    EXPECT_EQ(actions_of(keys::o, key_mods::alt), V{Shortcut::outline});
    EXPECT_EQ(actions_of(keys::r, key_mods::ctrl), V{Shortcut::script_camera});
    EXPECT_EQ(actions_of(keys::home, 0), V{Shortcut::script_camera});
    EXPECT_EQ(actions_of(keys::e, key_mods::alt), V{Shortcut::exposure_up});
    EXPECT_EQ(actions_of(keys::e, key_mods::alt | key_mods::shift), V{Shortcut::exposure_down});
    EXPECT_EQ(actions_of(keys::e, key_mods::ctrl), V{Shortcut::exposure_reset});
    EXPECT_EQ(actions_of(keys::z, key_mods::ctrl), V{Shortcut::undo});
    EXPECT_EQ(actions_of(keys::z, key_mods::ctrl | key_mods::shift), V{Shortcut::redo});
    EXPECT_EQ(actions_of(keys::s, key_mods::ctrl), V{Shortcut::save});
    EXPECT_EQ(actions_of(keys::f1, key_mods::shift), V{Shortcut::help});
    EXPECT_EQ(actions_of(keys::space, 0), V{Shortcut::pause});
    EXPECT_TRUE(actions_of(keys::o, key_mods::ctrl | key_mods::alt).empty()) << "modifiers match exactly";
    KeyEvents events;  // auto-repeats step the arrows and undo, not the toggles
    events.press(keys::left, 0, true);
    events.press(keys::o, key_mods::alt, true);
    events.begin_frame();
    EXPECT_EQ(shortcuts_pressed(events, false), V{Shortcut::orbit_left});
}

TEST(Shortcuts, NothingActsWhileAWidgetHasTheKeyboard) {
    for (const ShortcutBinding& b : shortcut_bindings())
        EXPECT_TRUE(actions_of(b.key, b.mods, true).empty()) << "key " << b.key << " mods " << b.mods;
}

/// How the help writes a binding's keys: "Alt+Shift+E", "F5", "arrow keys".
std::string help_name(const ShortcutBinding& b) {
    std::string name;
    if (b.mods & key_mods::ctrl) name += "Ctrl+";
    if (b.mods & key_mods::alt) name += "Alt+";
    if (b.mods & key_mods::shift) name += "Shift+";
    switch (b.key) {
    case keys::f1: return name + "F1";
    case keys::f5: return name + "F5";
    case keys::escape: return name + "Esc";
    case keys::home: return name + "Home";
    case keys::tab: return name + "Tab";
    case keys::space: return name + "Space";
    case keys::left: case keys::right: case keys::up: case keys::down: return "arrow keys";
    case keys::keypad_add: return name + "=";  // the help names the main key of the pair
    case keys::keypad_subtract: return name + "-";
    default: return name + static_cast<char>(b.key);
    }
}

TEST(Shortcuts, TheHelpNamesEveryShortcut) {
    const auto rows = shortcut_help_rows();
    for (const ShortcutBinding& b : shortcut_bindings()) {
        const std::string name = help_name(b);
        const bool listed = std::any_of(rows.begin(), rows.end(), [&](const auto& row) {
            const std::string& keys_text = row.first;
            for (std::size_t at = keys_text.find(name); at != std::string::npos; at = keys_text.find(name, at + 1)) {
                const std::size_t end = at + name.size();
                const bool starts = at == 0 || keys_text[at - 1] == ' ' || keys_text[at - 1] == ',';
                const bool ends = end == keys_text.size() || keys_text[end] == ' ' || keys_text[end] == ',';
                if (starts && ends) return true;
            }
            return false;
        });
        EXPECT_TRUE(listed) << name;
    }
}

TEST(KeyEvents, AfterKeyIsAScriptedRunsOption) {
    EXPECT_FALSE(parse_view_arguments({"scene.lua", "--frames", "3"}).after_key);
    const ViewArguments args = parse_view_arguments({"scene.lua", "--frames", "3", "--after-key"});
    EXPECT_TRUE(args.after_key);
    EXPECT_EQ(args.scene, "scene.lua");
    EXPECT_TRUE(args.option_tokens.empty()) << "not taken for a render option";
    EXPECT_NE(view_help().find("--after-key"), std::string::npos);
}

using namespace caustica::ui::testing;
using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) { return std::chrono::duration<double>(clock_type::now() - t0).count(); }

TEST(FramePacing, ANewViewsCoarsePreviewEndsTheWaitAtOnceAndNothingElseDoes) {
    TempFolder folder;
    ModelConfig config;
    config.option_tokens = {"--reproducible", "--threads", "2"};
    ViewModel model(config);
    model.open(folder.write("scene.lua", caustic_box_text(20000)));
    ASSERT_TRUE(run_until_finished(model)) << model.error();
    EXPECT_EQ(coarse_preview(model.driver()), CoarsePreview::none);

    // Nothing new to show: the frame comes at its time, not before.
    FramePacing pacing;
    pacing.period = std::chrono::milliseconds(40);
    auto t0 = clock_type::now();
    wait_for_next_frame(model, t0, pacing);
    EXPECT_GE(seconds_since(t0), 0.040);

    // A camera move (the frame reading it: update() restarts the render). Its coarse preview is
    // being rendered, or already complete and not shown yet; the wait ends when it is complete,
    // long before a frame period of 30 s.
    model.orbit(10.0, 0.0);
    model.update();
    EXPECT_NE(coarse_preview(model.driver()), CoarsePreview::none);
    FrameSkipper never_drawn;
    EXPECT_FALSE(never_drawn.may_skip(model.driver())) << "the screen is old: draw it";
    const double period = caustica::testing::time_bound(30.0);
    pacing.period = std::chrono::milliseconds(static_cast<long long>(period * 1000.0));
    t0 = clock_type::now();
    int polls = 0;
    wait_for_next_frame(model, t0, pacing, [&] { ++polls; });
    EXPECT_LT(seconds_since(t0), 2.0 / 3.0 * period);
    EXPECT_GE(polls, 1);
    EXPECT_EQ(coarse_preview(model.driver()), CoarsePreview::unshown);
    const SessionProgress live = model.driver().session().progress();
    EXPECT_GE(live.tiles_done, live.tiles_total / static_cast<std::size_t>(live.passes));

    // The next frame fetches it: nothing more to wait for, and that frame is drawn.
    model.update();
    EXPECT_EQ(coarse_preview(model.driver()), CoarsePreview::none);
    FrameSkipper skipper;
    skipper.drawn();
    EXPECT_FALSE(skipper.may_skip(model.driver())) << "it brings a view not shown yet";
    const std::uint64_t generation = model.driver().generation();
    EXPECT_TRUE(std::all_of(model.driver().changed_generations().begin(), model.driver().changed_generations().end(),
                            [&](std::uint64_t g) { return g == generation; }));
    EXPECT_FALSE(model.driver().changed_tiles().empty());
    ASSERT_TRUE(run_until_finished(model)) << model.error();
}

TEST(FramePacing, TheFrameReadingAMoveIsNotDrawnButTheOneShowingItsPreviewIs) {
    // The frame reading a move may stay undrawn for max_undrawn after the last drawn one; between
    // the two the test restarts a render, which a sanitizer on a slow machine stretches past the
    // 60 ms the loop allows: the bound is scaled like every other (measured before the render).
    FramePacing pacing;
    pacing.max_undrawn = std::chrono::microseconds(static_cast<long long>(caustica::testing::time_bound(0.06) * 1e6));
    TempFolder folder;
    ModelConfig config;
    config.option_tokens = {"--reproducible", "--threads", "2"};
    ViewModel model(config);
    model.open(folder.write("scene.lua", caustic_box_text(20000)));
    model.set_resolution_scale(4.0);  // 1024 x 768: a coarse pass of milliseconds, not microseconds
    ASSERT_TRUE(run_until_finished(model)) << model.error();
    FrameSkipper skipper;
    EXPECT_FALSE(skipper.may_skip(model.driver())) << "never drawn";
    clock_type::time_point drawn_at = clock_type::now();  // at or before the skipper's own mark
    skipper.drawn();
    // An attempt tells only when the frame reading the move fetched no tile of the new view (a
    // main thread descheduled between the restart and the fetch lets the workers finish some) and
    // came within max_undrawn of the last drawn frame; otherwise it must be drawn, and is retried.
    int skipped = 0;
    for (int attempt = 0; attempt < 10 && skipped == 0; ++attempt) {
        model.orbit(5.0, 0.0);
        model.update();  // the frame reading the move: restarts the render
        const bool skip = skipper.may_skip(model.driver(), pacing);
        const bool in_time = clock_type::now() - drawn_at < pacing.max_undrawn;
        const std::uint64_t generation = model.driver().generation();
        const bool new_tiles = std::any_of(model.driver().changed_generations().begin(),
                                           model.driver().changed_generations().end(),
                                           [&](std::uint64_t g) { return g == generation; });
        if (new_tiles) {
            EXPECT_FALSE(skip) << "it brings tiles of the new view";
        }
        if (coarse_preview(model.driver()) != CoarsePreview::rendering || new_tiles || !in_time) {
            // (still rendering now: so it was when the skipper looked)
            ASSERT_TRUE(run_until_finished(model));  // the preview was too quick to see: again
            skipper.may_skip(model.driver());
            drawn_at = clock_type::now();
            skipper.drawn();
            continue;
        }
        EXPECT_TRUE(skip);
        ++skipped;
        wait_for_next_frame(model, clock_type::now());
        model.update();  // the frame showing the preview (or its first blocks, after the grace time)
        EXPECT_FALSE(skipper.may_skip(model.driver())) << "it brings the new view";
        skipper.drawn();
    }
    EXPECT_EQ(skipped, 1) << "the coarse pass was never seen running";
    ASSERT_TRUE(run_until_finished(model)) << model.error();
}

}  // namespace
}  // namespace caustica::ui
