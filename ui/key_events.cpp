#include "ui/key_events.h"

#include <algorithm>

namespace caustica::ui {

void KeyEvents::press(int key, int mods, bool repeat) {
    if (pending_.size() >= max_pending) return;
    pending_.push_back(KeyPress{key, mods & key_mods::all, repeat});
    if (!repeat && std::find(pressed_.begin(), pressed_.end(), key) == pressed_.end()) pressed_.push_back(key);
}

void KeyEvents::release(int key) {
    const auto it = std::find(pressed_.begin(), pressed_.end(), key);
    if (it == pressed_.end()) return;  // pressed before this frame: ImGui saw it down
    pressed_.erase(it);
    if (std::find(pending_taps_.begin(), pending_taps_.end(), key) == pending_taps_.end()) pending_taps_.push_back(key);
}

void KeyEvents::begin_frame() {
    frame_.swap(pending_);
    pending_.clear();
    lifts_.swap(taps_);
    taps_.swap(pending_taps_);
    pending_taps_.clear();
    pressed_.clear();
}

void KeyEvents::clear() {
    pending_.clear();
    frame_.clear();
    pressed_.clear();
    pending_taps_.clear();
    taps_.clear();
    lifts_.clear();
}

bool KeyEvents::pressed_with(int key, int mods, bool repeat) const {
    return std::any_of(frame_.begin(), frame_.end(), [&](const KeyPress& p) {
        return p.key == key && (repeat || !p.repeat) && p.mods == (mods & key_mods::all);
    });
}

int KeyEvents::count(int key, bool repeat) const {
    return static_cast<int>(
        std::count_if(frame_.begin(), frame_.end(), [&](const KeyPress& p) { return p.key == key && (repeat || !p.repeat); }));
}

KeyEvents& key_events() {
    static KeyEvents events;  // the GLFW callbacks and the frame loop run on the main thread
    return events;
}

bool key_pressed(int imgui_key, bool repeat) { return key_events().pressed(imgui_key, repeat); }

bool key_pressed_with(int imgui_key, int mods, bool repeat) {
    return key_events().pressed_with(imgui_key, mods, repeat);
}

}  // namespace caustica::ui
