// Internal to the ViewModel's sources (ui/view_model*.cpp): the small helpers more than one of
// them uses.
#pragma once

#include "core/scene/scene_desc.h"

#include <algorithm>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace caustica::ui {

inline bool same_camera(const CameraDesc& a, const CameraDesc& b) {
    return a.eye == b.eye && a.view == b.view && a.up == b.up && a.fovy_degrees == b.fovy_degrees;
}

inline bool same_file(const std::string& a, const std::string& b) {
    if (a.empty() || b.empty()) return false;
    std::error_code ec;
    const bool same = std::filesystem::equivalent(a, b, ec);
    return ec ? a == b : same;
}

inline std::string absolute_path(const std::string& path) {
    std::error_code ec;
    const std::filesystem::path p = std::filesystem::weakly_canonical(std::filesystem::absolute(path), ec);
    return ec ? path : p.string();
}

inline bool has_token(const std::vector<std::string>& tokens, const std::string& token) {
    return std::find(tokens.begin(), tokens.end(), token) != tokens.end();
}

}  // namespace caustica::ui
