#include "core/util/printable_text.h"

#include <algorithm>
#include <cstdio>

namespace caustica {
namespace {

/// The length of the UTF-8 character at the start of `text` (1 to 4), or 0 when its bytes are not
/// UTF-8: a stray continuation byte, a truncated or overlong sequence, a surrogate, a code point
/// past U+10FFFF (the well-formed sequences of the Unicode standard, table 3-7).
std::size_t utf8_length(std::string_view text) {
    const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
    const unsigned char lead = byte(0);
    if (lead < 0x80) return 1;
    std::size_t length = 0;
    unsigned char second_low = 0x80, second_high = 0xbf;
    if (lead >= 0xc2 && lead <= 0xdf) {
        length = 2;
    } else if (lead >= 0xe0 && lead <= 0xef) {
        length = 3;
        if (lead == 0xe0) second_low = 0xa0;   // overlong below
        if (lead == 0xed) second_high = 0x9f;  // surrogates above
    } else if (lead >= 0xf0 && lead <= 0xf4) {
        length = 4;
        if (lead == 0xf0) second_low = 0x90;   // overlong below
        if (lead == 0xf4) second_high = 0x8f;  // past U+10FFFF above
    } else {
        return 0;
    }
    if (text.size() < length || byte(1) < second_low || byte(1) > second_high) return 0;
    for (std::size_t i = 2; i < length; ++i)
        if ((byte(i) & 0xc0) != 0x80) return 0;
    return length;
}

/// True for the characters a terminal acts on: C0 controls but newline and tab, and DEL.
bool is_control(unsigned char c) {
    return (c < 0x20 && c != '\n' && c != '\t') || c == 0x7f;
}

/// How the character at the start of `text` is shown, and how many bytes of `text` it stands for.
/// An escaped form is written into `buffer`.
std::string_view shown_character(std::string_view text, char (&buffer)[8], std::size_t& bytes) {
    const std::size_t length = utf8_length(text);
    const auto lead = static_cast<unsigned char>(text[0]);
    bytes = length == 0 ? 1 : length;
    if (length == 0 || (length == 1 && is_control(lead))) {
        std::snprintf(buffer, sizeof buffer, "\\x%02x", lead);
        return {buffer, 4};
    }
    if (length == 2 && lead == 0xc2 && static_cast<unsigned char>(text[1]) <= 0x9f) {  // C1: U+0080..U+009F
        std::snprintf(buffer, sizeof buffer, "\\u%04x", static_cast<unsigned char>(text[1]));
        return {buffer, 6};
    }
    return text.substr(0, length);
}

}  // namespace

std::string printable_text(std::string_view text, std::size_t limit, std::size_t more_bytes) {
    std::string out;
    out.reserve(std::min(text.size(), limit));
    std::size_t at = 0;
    char buffer[8];
    while (at < text.size()) {
        std::size_t bytes = 0;
        const std::string_view form = shown_character(text.substr(at), buffer, bytes);
        if (out.size() + form.size() > limit) break;
        out += form;
        at += bytes;
    }
    const std::size_t left = text.size() - at + more_bytes;
    if (left > 0) out += " … and " + std::to_string(left) + " more bytes";
    return out;
}

std::optional<std::string> ScriptOutputBudget::admit(std::string_view text, std::size_t more_bytes) {
    if (!spent_) {
        std::string shown = printable_text(text, piece_limit_, more_bytes);
        if (shown.size() + 1 <= total_limit_ - used_) {
            used_ += shown.size() + 1;
            return shown;
        }
        spent_ = true;
    }
    left_out_ += text.size() + more_bytes;
    return std::nullopt;
}

std::string ScriptOutputBudget::summary(std::string_view what) const {
    if (left_out_ == 0) return {};
    return "… and " + std::to_string(left_out_) + " more bytes of " + std::string(what) + " left out (at most " +
           std::to_string(total_limit_ >> 10) + " KiB are shown)";
}

}  // namespace caustica
