// printable_text and ScriptOutputBudget (core/util/printable_text.h): what becomes visible, what
// passes unchanged, and how text and floods of it are cut with what was left out counted
// (docs/RELIABILITY.md, "Script text reaches the user bounded and visible").
#include "core/util/printable_text.h"
#include "tests/time_bounds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>

namespace caustica {
namespace {

using Clock = std::chrono::steady_clock;

TEST(PrintableText, EscapeAndControlCharactersBecomeVisible) {
    EXPECT_EQ(printable_text("\x1b[2J\x1b]0;title\x07"), "\\x1b[2J\\x1b]0;title\\x07");
    EXPECT_EQ(printable_text("a\rb\x7f\x01"), "a\\x0db\\x7f\\x01");
    EXPECT_EQ(printable_text("\xc2\x9b" "2J \xc2\x9d"), "\\u009b2J \\u009d");  // C1 CSI and OSC
    EXPECT_EQ(printable_text("\xff \xc3 \xed\xa0\x80 \xc0\xaf"), "\\xff \\xc3 \\xed\\xa0\\x80 \\xc0\\xaf");
    EXPECT_EQ(printable_text("line 1\n\tline 2"), "line 1\n\tline 2");
}

TEST(PrintableText, Utf8PassesUnchanged) {
    for (const char* text : {"café", "naïve Ωμέγα", "日本語", "\xf0\x9f\x8c\x88 rainbow", "\xc2\xa0 no-break"})
        EXPECT_EQ(printable_text(text), text);
}

TEST(PrintableText, LongTextIsCutAndSaysHowMuchWasLeftOut) {
    const std::string long_text(50'000'000, 'E');
    const auto start = Clock::now();
    const std::string shown = printable_text(long_text, script_text_limit);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    EXPECT_LT(seconds, testing::time_bound(0.1));  // the cut is found without reading the rest
    EXPECT_LE(shown.size(), printable_text_max_bytes(script_text_limit));
    const std::size_t kept = static_cast<std::size_t>(std::count(shown.begin(), shown.end(), 'E'));
    EXPECT_EQ(shown, std::string(kept, 'E') + " … and " + std::to_string(50'000'000 - kept) + " more bytes");
    // Escaped text counts what it shows, never cutting a character or an escape in two.
    const std::string escapes = printable_text(std::string(100, '\x1b'), 10, 7);
    EXPECT_EQ(escapes, "\\x1b\\x1b … and 105 more bytes");
    // Already printable text is left as it is, so each stage may apply it again.
    EXPECT_EQ(printable_text(shown, printable_text_max_bytes(script_text_limit)), shown);
}

TEST(PrintableText, OutputBudgetBoundsAFloodAndCountsTheRest) {
    ScriptOutputBudget budget;
    std::size_t shown_bytes = 0, refused = 0;
    for (int i = 0; i < 100'000; ++i) {
        if (const std::optional<std::string> piece = budget.admit(std::string(100, 'p'))) shown_bytes += piece->size() + 1;
        else ++refused;
    }
    EXPECT_EQ(shown_bytes, budget.used());
    EXPECT_LE(shown_bytes, script_output_limit);
    EXPECT_GT(shown_bytes, script_output_limit - 101);  // whole pieces, as many as fit
    EXPECT_EQ(budget.left_out(), refused * 100);
    EXPECT_EQ(budget.summary("script output"),
              "… and " + std::to_string(refused * 100) + " more bytes of script output left out (at most 64 KiB are shown)");
    EXPECT_EQ(ScriptOutputBudget().summary("script output"), "");
    // Each piece is cut to the piece limit; the first piece that would pass the total and every
    // one after it are refused whole, so what is shown is whole pieces, in order.
    ScriptOutputBudget small(100, 30);
    EXPECT_EQ(small.admit(std::string(50, 'x')).value_or("(refused)"), std::string(30, 'x') + " … and 20 more bytes");
    EXPECT_EQ(small.admit("y").value_or("(refused)"), "y");
    EXPECT_FALSE(small.admit(std::string(50, 'z')).has_value());
    EXPECT_FALSE(small.admit("y").has_value());
    EXPECT_EQ(small.used(), 55u);
    EXPECT_EQ(small.left_out(), 51u);
}

}  // namespace
}  // namespace caustica
