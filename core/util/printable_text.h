// Text a scene script chose (an error value, a warning, what print and io.write write, a node's
// name inside a message) on its way to the user: bounded, and with every character that a
// terminal would act on made visible (docs/RELIABILITY.md, "Script text reaches the user bounded
// and visible"). The loader applies it where the text is made, the caller again where the loader's
// answer is read, and the terminal, the preview and image metadata where it is shown.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace caustica {

/// Bytes kept of one piece of a script's text: an error value, a warning, one print or io.write.
inline constexpr std::size_t script_text_limit = 4096;
/// Bytes kept of one message as shown: a script's text with what caustica says around it (file,
/// line, call, the scene's path).
inline constexpr std::size_t shown_message_limit = 2 * script_text_limit;
/// Bytes one run of a script may print and warn in all.
inline constexpr std::size_t script_output_limit = 64 * 1024;

/// `text` as it may be shown: control characters (below 0x20 but newline and tab, and 0x7f)
/// become "\x1b", C1 characters (U+0080 to U+009F) "\u009b", bytes that are not UTF-8 "\xff";
/// other UTF-8 passes unchanged. At most `limit` bytes of that are kept, whole characters only;
/// when anything is cut, " … and N more bytes" follows, N counting the bytes of `text` not shown
/// plus `more_bytes` (bytes the caller left out before). Already printable text within `limit`
/// comes back unchanged.
std::string printable_text(std::string_view text, std::size_t limit = shown_message_limit,
                           std::size_t more_bytes = 0);

/// The longest answer printable_text(..., limit, ...) gives: `limit` and the longest summary.
constexpr std::size_t printable_text_max_bytes(std::size_t limit) {
    return limit + sizeof(" … and  more bytes") - 1 + 20;  // 20 digits: the largest size_t
}

/// Bounds what one run of a script prints and warns: each piece to `piece_limit` bytes, all of
/// them together to `total_limit`. The first piece that would pass the total, and every piece
/// after it, are only counted: what is shown is whole pieces, in order.
class ScriptOutputBudget {
public:
    explicit ScriptOutputBudget(std::size_t total_limit = script_output_limit,
                                std::size_t piece_limit = script_text_limit)
        : total_limit_(total_limit), piece_limit_(piece_limit) {}

    /// The piece as it may be shown (printable_text; `more_bytes` were cut from it already), or
    /// nothing once the budget is spent. Each piece costs its shown bytes and one for the end of
    /// its line, so that empty pieces cannot go on for ever either.
    std::optional<std::string> admit(std::string_view text, std::size_t more_bytes = 0);
    /// Bytes of the pieces shown, one more for each.
    std::size_t used() const { return used_; }
    /// Bytes of the pieces refused whole.
    std::size_t left_out() const { return left_out_; }
    /// "… and N more bytes of `what` left out (at most 64 KiB are shown)", or "" when none was.
    std::string summary(std::string_view what) const;

private:
    std::size_t total_limit_;
    std::size_t piece_limit_;
    std::size_t used_ = 0;
    std::size_t left_out_ = 0;
    bool spent_ = false;
};

}  // namespace caustica
