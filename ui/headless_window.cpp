#include "ui/headless_window.h"

#include "ui/key_events.h"
#include "ui/keys.h"

#include <GL/osmesa.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <stdexcept>

namespace caustica::ui {

struct HeadlessWindow::Context {
    OSMesaContext gl = nullptr;
    std::vector<unsigned char> buffer;  // RGBA8, bottom row first (OSMesa's default)
};

namespace {

/// ImGui's navigation keys mapped to our (GLFW) key numbers, as the GLFW backend does.
void map_keys(ImGuiIO& io) {
    io.KeyMap[ImGuiKey_Tab] = keys::tab;
    io.KeyMap[ImGuiKey_LeftArrow] = keys::left;
    io.KeyMap[ImGuiKey_RightArrow] = keys::right;
    io.KeyMap[ImGuiKey_UpArrow] = keys::up;
    io.KeyMap[ImGuiKey_DownArrow] = keys::down;
    io.KeyMap[ImGuiKey_PageUp] = keys::page_up;
    io.KeyMap[ImGuiKey_PageDown] = keys::page_down;
    io.KeyMap[ImGuiKey_Home] = keys::home;
    io.KeyMap[ImGuiKey_End] = keys::end;
    io.KeyMap[ImGuiKey_Insert] = keys::insert;
    io.KeyMap[ImGuiKey_Delete] = keys::del;
    io.KeyMap[ImGuiKey_Backspace] = keys::backspace;
    io.KeyMap[ImGuiKey_Space] = keys::space;
    io.KeyMap[ImGuiKey_Enter] = keys::enter;
    io.KeyMap[ImGuiKey_Escape] = keys::escape;
    io.KeyMap[ImGuiKey_KeyPadEnter] = keys::keypad_enter;
    io.KeyMap[ImGuiKey_A] = keys::a;
    io.KeyMap[ImGuiKey_C] = keys::c;
    io.KeyMap[ImGuiKey_V] = keys::v;
    io.KeyMap[ImGuiKey_X] = keys::x;
    io.KeyMap[ImGuiKey_Y] = keys::y;
    io.KeyMap[ImGuiKey_Z] = keys::z;
}

}  // namespace

HeadlessWindow::HeadlessWindow(int width, int height)
    : context_(std::make_unique<Context>()), width_(width), height_(height) {
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_STENCIL_BITS, 0,
                              OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 3,
                              OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    context_->gl = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!context_->gl) throw std::runtime_error("OSMesa: cannot create an OpenGL 3.3 core context");
    context_->buffer.assign(static_cast<std::size_t>(width) * height * 4, 0);
    if (!OSMesaMakeCurrent(context_->gl, context_->buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
        OSMesaDestroyContext(context_->gl);
        throw std::runtime_error("OSMesa: cannot make the context current");
    }
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
    map_keys(io);
    apply_panel_style();
    key_events().clear();
    // The backend's GL loader finds OSMesa through the dlopen/dlsym shim (osmesa_loader_shim.cpp).
    if (!ImGui_ImplOpenGL3_Init("#version 330 core")) {
        ImGui::DestroyContext();
        OSMesaDestroyContext(context_->gl);
        throw std::runtime_error("ImGui OpenGL3 renderer: cannot load OpenGL functions from OSMesa");
    }
    last_frame_ = std::chrono::steady_clock::now();
}

HeadlessWindow::~HeadlessWindow() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui::DestroyContext();
    OSMesaDestroyContext(context_->gl);
}

void HeadlessWindow::frame(ViewApp& app, const HeadlessInput& input) {
    ImGuiIO& io = ImGui::GetIO();
    const auto now = std::chrono::steady_clock::now();
    io.DeltaTime = std::max(1e-4f, std::chrono::duration<float>(now - last_frame_).count());
    last_frame_ = now;
    io.DisplaySize = ImVec2(static_cast<float>(width_), static_cast<float>(height_));
    io.MousePos = ImVec2(input.mouse.x, input.mouse.y);
    for (int b = 0; b < 3; ++b) io.MouseDown[b] = input.buttons[b];
    io.MouseWheel = input.wheel;
    io.KeyCtrl = input.ctrl;
    io.KeyShift = input.shift;
    io.KeyAlt = input.alt;
    // A key listed in this frame but not the last is a new press (for ViewApp's key queue too);
    // one listed in both is held: no second press, no auto-repeat.
    const int mods = (input.ctrl ? key_mods::ctrl : 0) | (input.shift ? key_mods::shift : 0) |
                     (input.alt ? key_mods::alt : 0);
    for (int key : input.keys)
        if (std::find(released_.begin(), released_.end(), key) == released_.end()) key_events().press(key, mods);
    for (int key : input.taps) {
        key_events().press(key, mods);
        key_events().release(key);
    }
    key_events().begin_frame();
    for (int key : released_) io.KeysDown[key] = false;
    for (int key : key_events().lifts()) io.KeysDown[key] = false;
    for (int key : key_events().taps()) io.KeysDown[key] = true;  // down for this frame, as the window shows taps
    for (int key : input.keys) io.KeysDown[key] = true;
    released_ = input.keys;

    using ms = std::chrono::duration<double, std::milli>;
    ImGui_ImplOpenGL3_NewFrame();
    ImGui::NewFrame();
    app.frame(glm::vec2(width_, height_));
    ImGui::Render();
    const auto built = std::chrono::steady_clock::now();
    times_.build = ms(built - now).count();
    drawn_ = !(skip_for_ && skipper_.may_skip(skip_for_->driver()) && skipping_);
    if (!drawn_) {
        times_.draw = times_.draw_image = 0.0;
        return;
    }
    app.draw(glm::vec2(width_, height_), width_, height_);
    if (measure_draw_) glFinish();  // separates the image's share (costs a little parallelism)
    const auto image_drawn = std::chrono::steady_clock::now();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    glFinish();
    skipper_.drawn();
    times_.draw = ms(std::chrono::steady_clock::now() - built).count();
    times_.draw_image = ms(image_drawn - built).count();
}

void HeadlessWindow::skip_undrawable_frames(const ViewModel* model, bool on) {
    if (model != skip_for_) skipper_ = FrameSkipper();
    skip_for_ = model;
    skipping_ = on;
}

std::vector<unsigned char> HeadlessWindow::pixels() const {
    std::vector<unsigned char> rgba(context_->buffer.size());
    const std::size_t row = static_cast<std::size_t>(width_) * 4;
    for (int y = 0; y < height_; ++y)
        std::copy_n(&context_->buffer[static_cast<std::size_t>(height_ - 1 - y) * row], row, &rgba[y * row]);
    return rgba;
}

}  // namespace caustica::ui
