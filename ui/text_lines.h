// Lines of a status made of parts ("16 of 16 passes", "320M photons", ...): broken only between
// parts, so that a number is never split across lines as a word wrap at '.' would split it.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace caustica::ui {

/// `parts` joined by `separator` into lines no wider than `width` as `measure` measures text,
/// breaking only between parts; a part wider than `width` stands alone on its line.
inline std::vector<std::string> lines_of_parts(const std::vector<std::string>& parts, const std::string& separator,
                                               float width, const std::function<float(const std::string&)>& measure) {
    std::vector<std::string> lines;
    for (const std::string& part : parts) {
        if (!lines.empty() && measure(lines.back() + separator + part) <= width)
            lines.back() += separator + part;
        else
            lines.push_back(part);
    }
    return lines;
}

}  // namespace caustica::ui
