// Headless tests of the knobs in the sidebar (docs/PREVIEW.md, "Panels"): a drag on a
// logarithmic knob changes it by a bounded factor a pixel (Shift: coarse), Ctrl+click types, and
// no control moves under the cursor: not while the difference row of its change appears, not when
// the sidebar, scrolled to its end, gets shorter.
#include "headless_preview.h"

#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h>

#include <algorithm>
#include <map>
#include <string>

namespace caustica::ui {
namespace {

using namespace caustica::ui::testing;

using Preview = HeadlessPreview;

/// Where the knob's drag field was drawn in the last frame.
PanelState::WidgetRect knob_rect(Preview& preview, const std::string& knob) {
    const std::map<std::string, PanelState::WidgetRect>& rects = preview.app->panels().knob_rects;
    const auto found = rects.find(knob);
    return found == rects.end() ? PanelState::WidgetRect{glm::vec2(-1.0f), glm::vec2(-1.0f)} : found->second;
}

/// A frame's input with the mouse at `point` and the wheel turned by `wheel`.
HeadlessInput mouse_at(glm::vec2 point, float wheel = 0.0f) {
    HeadlessInput input;
    input.mouse = point;
    input.wheel = wheel;
    return input;
}

bool differs(const ViewModel& model, const std::string& label) {
    const std::vector<Difference> differences = model.differences();
    return std::any_of(differences.begin(), differences.end(), [&](const Difference& d) { return d.label == label; });
}

/// Drags the knob `pixels` to the right from its middle, frame by frame (a pixel a frame), and
/// returns whether its drag field stayed where it was in every frame.
bool drag_knob(Preview& preview, const std::string& knob, int pixels, bool shift) {
    const PanelState::WidgetRect start = knob_rect(preview, knob);
    HeadlessInput input;
    input.mouse = 0.5f * (start.min + start.max);
    input.shift = shift;
    preview.frame(input);  // hover first, as a person does
    input.buttons[0] = true;
    preview.frame(input);
    bool stayed = true;
    for (int i = 0; i < pixels; ++i) {
        input.mouse.x += 1.0f;
        preview.frame(input);
        stayed = stayed && knob_rect(preview, knob).min == start.min;
    }
    input.buttons[0] = false;
    preview.frame(input);
    preview.frame(input);
    return stayed && knob_rect(preview, knob).min == start.min;
}

TEST(SnapshotKnobs, ADragIsFineShiftIsCoarseAndTheKnobStaysAsItsDifferenceAppears) {
    Preview preview(caustic_box_text(100000, "gr.option('--caustic-num-neighbours 25')"));
    ASSERT_TRUE(preview.settle()) << preview.model->error();
    ASSERT_EQ(preview.model->knobs().num_neighbours, 25);
    ASSERT_FALSE(differs(*preview.model, "neighbours N"));
    const PanelState::WidgetRect rect = knob_rect(preview, "neighbours N");
    ASSERT_GT(rect.min.y, 0.0f);
    ASSERT_LT(rect.max.y, static_cast<float>(window_height));  // on screen, where a person drags it

    // 29 pixels (a slider spanning six decades takes them from 25 to 2565): a little more than 25,
    // and the row "neighbours N 25 -> ..." appears above the knob without moving it.
    EXPECT_TRUE(drag_knob(preview, "neighbours N", 29, false));
    const int fine = preview.model->knobs().num_neighbours;
    EXPECT_GT(fine, 25);
    EXPECT_LE(fine, 37);
    EXPECT_TRUE(differs(*preview.model, "neighbours N"));
    EXPECT_EQ(knob_rect(preview, "neighbours N").min, rect.min);
    write_doc_image(preview.snapshot(), "knobs_fine_drag.png");

    // The same drag with Shift goes much further.
    EXPECT_TRUE(drag_knob(preview, "neighbours N", 29, true));
    EXPECT_GT(preview.model->knobs().num_neighbours, 4 * fine);

    // The difference reset: its row goes, the knob stays.
    preview.model->reset_difference("all");
    for (int i = 0; i < 3; ++i) preview.frame(HeadlessInput{});
    EXPECT_EQ(preview.model->knobs().num_neighbours, 25);
    EXPECT_FALSE(differs(*preview.model, "neighbours N"));
    EXPECT_EQ(knob_rect(preview, "neighbours N").min, rect.min);

    // A click alone changes nothing; Ctrl+click gives the keyboard to the field beside the knob.
    EXPECT_TRUE(drag_knob(preview, "neighbours N", 0, false));
    EXPECT_EQ(preview.model->knobs().num_neighbours, 25);
    HeadlessInput click;
    click.mouse = 0.5f * (rect.min + rect.max);
    click.ctrl = true;
    preview.frame(click);
    click.buttons[0] = true;
    preview.frame(click);
    click.buttons[0] = false;
    for (int i = 0; i < 3; ++i) preview.frame(click);
    EXPECT_TRUE(ImGui::GetIO().WantTextInput);
    EXPECT_EQ(preview.model->knobs().num_neighbours, 25);
}

/// Whether a tooltip was drawn in the last frame.
bool tooltip_shown() {
    for (const ImGuiWindow* window : ImGui::GetCurrentContext()->Windows)
        if ((window->Flags & ImGuiWindowFlags_Tooltip) && window->Active) return true;
    return false;
}

TEST(SnapshotKnobs, AKnobsTooltipShowsOnHoverAndNotWhileItIsDragged) {
    Preview preview(caustic_box_text(100000));
    ASSERT_TRUE(preview.settle()) << preview.model->error();
    const PanelState::WidgetRect rect = knob_rect(preview, "neighbours N");
    HeadlessInput input;
    input.mouse = 0.5f * (rect.min + rect.max);
    preview.frame(input);
    preview.frame(input);
    EXPECT_TRUE(tooltip_shown());  // hovered: what the knob does and how it is dragged
    input.buttons[0] = true;
    for (int i = 0; i < 6; ++i) {
        input.mouse.x += 1.0f;
        preview.frame(input);
        EXPECT_FALSE(tooltip_shown()) << "frame " << i << " of the drag";  // the rows below stay in view
    }
    input.buttons[0] = false;
    preview.frame(input);
    preview.frame(input);
    EXPECT_TRUE(tooltip_shown());
}

TEST(SnapshotKnobs, TheSidebarScrolledToItsEndDoesNotMoveWhenItGetsShorter) {
    Preview preview(caustic_box_text(100000));
    ASSERT_TRUE(preview.settle()) << preview.model->error();
    // Global illumination on: two more knobs make the sidebar longer; then scroll to its end.
    CausticKnobs knobs = preview.model->knobs();
    knobs.gi = true;
    knobs.gi_photons = 1000;
    preview.model->set_knobs(knobs);
    for (int i = 0; i < 3; ++i) preview.frame(HeadlessInput{});
    const float unscrolled = knob_rect(preview, "photons").min.y;
    const glm::vec2 statistics(window_width - 200.0f, window_height - 20.0f);
    preview.frame(mouse_at(statistics, -50.0f));
    for (int i = 0; i < 3; ++i) preview.frame(mouse_at(statistics));
    const PanelState::WidgetRect scrolled = knob_rect(preview, "photons");
    ASSERT_LT(scrolled.min.y, unscrolled);  // the sidebar is longer than the window, and scrolled
    ASSERT_GT(knob_rect(preview, "GI neighbours").min.y, 0.0f);

    // Global illumination off: the GI knobs go from below, and nothing above them moves.
    knobs.gi = false;
    preview.model->set_knobs(knobs);
    for (int i = 0; i < 3; ++i) preview.frame(mouse_at(statistics));
    EXPECT_EQ(knob_rect(preview, "photons").min, scrolled.min);
    // Scrolling up takes the blank end away again: at the top, the photons knob is where it was.
    preview.frame(mouse_at(statistics, 50.0f));
    for (int i = 0; i < 3; ++i) preview.frame(mouse_at(statistics));
    EXPECT_EQ(knob_rect(preview, "photons").min.y, unscrolled);
}

}  // namespace
}  // namespace caustica::ui
