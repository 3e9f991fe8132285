// caustica-view: the preview in a GLFW window (OpenGL 3.3 core through libOpenGL).
// `caustica view` execs this when there is a DISPLAY and no --headless.
#include "ui/frame_pacing.h"
#include "ui/key_events.h"
#include "ui/view_app.h"
#include "ui/view_main.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace caustica::ui;

int glfw_error_code = 0;
std::string glfw_error_text;

void on_glfw_error(int code, const char* text) {
    glfw_error_code = code;
    glfw_error_text = text ? text : "";
}

void on_drop(GLFWwindow* window, int count, const char** paths) {
    auto* app = static_cast<ViewApp*>(glfwGetWindowUserPointer(window));
    if (app) app->drop(std::vector<std::string>(paths, paths + count));
}

/// Set by the callbacks when something arrived that the next frame should answer at once: a key,
/// a button, the wheel, the pointer moving with a button held (a drag), a new window size.
bool input_arrived = false;

/// Records presses for ViewApp (ui/key_events.h); ImGui's GLFW backend, installed after this,
/// chains to it and then updates io.KeysDown, which alone would lose a tap shorter than a frame.
void on_key(GLFWwindow*, int key, int, int action, int mods) {
    if (action == GLFW_PRESS || action == GLFW_REPEAT) key_events().press(key, mods, action == GLFW_REPEAT);
    else if (action == GLFW_RELEASE) key_events().release(key);
    input_arrived = true;
}

void on_mouse_button(GLFWwindow*, int, int, int) { input_arrived = true; }

void on_scroll(GLFWwindow*, double, double) { input_arrived = true; }

void on_framebuffer_size(GLFWwindow*, int, int) { input_arrived = true; }

void on_cursor(GLFWwindow* window, double, double) {
    for (int b = GLFW_MOUSE_BUTTON_1; b <= GLFW_MOUSE_BUTTON_3; ++b)
        if (glfwGetMouseButton(window, b) == GLFW_PRESS) input_arrived = true;
}

/// Shows the keys tapped since the last frame down in io.KeysDown for this frame, so that ImGui's
/// own widgets see the tap too, and lifts the last frame's taps (ui/key_events.h).
void show_taps(GLFWwindow* window) {
    ImGuiIO& io = ImGui::GetIO();
    auto valid = [&](int key) { return key >= 0 && key < IM_ARRAYSIZE(io.KeysDown); };
    for (int key : key_events().lifts())
        if (valid(key) && glfwGetKey(window, key) != GLFW_PRESS) io.KeysDown[key] = false;
    for (int key : key_events().taps())
        if (valid(key)) io.KeysDown[key] = true;
}

void report_no_window() {
    std::fprintf(stderr, "caustica view: cannot open a window (GLFW error %d: %s).\n", glfw_error_code,
                 glfw_error_text.c_str());
    if (glfw_error_code == 65544 || glfw_error_code == 0x00010008)
        std::fprintf(stderr,
                     "There is no display to open it on. Use 'caustica view --headless ...' (OSMesa, no window;\n"
                     "with --snapshot FILE.png it writes what the window would show), or run under a virtual\n"
                     "display: xvfb-run -a -s \"-screen 0 1280x720x24\" caustica view ...\n");
}

/// Reads the back buffer (top row first).
std::vector<unsigned char> read_back_buffer(int width, int height) {
    std::vector<unsigned char> bottom_up(static_cast<std::size_t>(width) * height * 4), rgba(bottom_up.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
    const std::size_t row = static_cast<std::size_t>(width) * 4;
    for (int y = 0; y < height; ++y)
        std::copy_n(&bottom_up[(height - 1 - y) * row], row, &rgba[y * row]);
    return rgba;
}

int run_window(const ViewArguments& args) {
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        report_no_window();
        return 1;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    const std::string title = "caustica view" + (args.scene.empty() ? std::string() : " - " + args.scene);
    GLFWwindow* window = glfwCreateWindow(args.width, args.height, title.c_str(), nullptr, nullptr);
    if (!window) {
        report_no_window();
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // the layout is fixed: nothing to remember
    apply_panel_style();
    key_events().clear();
    // Ours before the backend's, which keeps them and calls them first.
    glfwSetKeyCallback(window, on_key);
    glfwSetMouseButtonCallback(window, on_mouse_button);
    glfwSetScrollCallback(window, on_scroll);
    glfwSetCursorPosCallback(window, on_cursor);
    glfwSetFramebufferSizeCallback(window, on_framebuffer_size);
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");
    int code = 0;
    {
        ViewModel model(model_config(args));
        ViewApp app(model);
        start_view(model, app.panels(), args);
        glfwSetWindowUserPointer(window, &app);
        glfwSetDropCallback(window, on_drop);
        ScriptedRun run(args);
        std::string shown_scene;
        FrameSkipper skipper;
        const auto min_frame_interval = std::chrono::milliseconds(4);  // input never runs frames faster
        bool polled_while_waiting = false;
        while (!glfwWindowShouldClose(window) && !app.quit_requested()) {
            // Idle, nothing renders: sleep until an event (file changes are polled 4 times a second),
            // unless the last wait already took one in.
            if (app.idle() && !args.scripted() && !polled_while_waiting) glfwWaitEventsTimeout(0.25);
            else glfwPollEvents();
            input_arrived = polled_while_waiting = false;
            const auto frame_start = std::chrono::steady_clock::now();
            key_events().begin_frame();
            show_taps(window);
            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            ImGui::NewFrame();
            int width = 0, height = 0, fb_width = 0, fb_height = 0;
            glfwGetWindowSize(window, &width, &height);
            glfwGetFramebufferSize(window, &fb_width, &fb_height);
            app.frame(glm::vec2(width, height));
            if (model.scene_path() != shown_scene) {  // the title names the scene shown
                shown_scene = model.scene_path();
                glfwSetWindowTitle(window, ("caustica view - " + shown_scene).c_str());
            }
            ImGui::Render();
            // A frame that would show the old image while a new view's coarse preview renders
            // leaves the screen as it is: its software GL would slow that preview down.
            bool drawn = !skipper.may_skip(model.driver());
            if (drawn) {
                app.draw(glm::vec2(width, height), fb_width, fb_height);
                ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            }
            if (args.scripted() && run.done(model)) {
                if (!drawn) {
                    app.draw(glm::vec2(width, height), fb_width, fb_height);
                    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
                }
                if (!args.snapshot.empty()) write_snapshot(args.snapshot, read_back_buffer(fb_width, fb_height), fb_width, fb_height, "glfw");
                code = scripted_exit_code(model, run);  // as the headless run: an error shown exits 2
                break;
            }
            if (drawn) {
                glfwSwapBuffers(window);
                skipper.drawn();
            }
            // Paced by the clock (Xvfb does not wait for vsync). While something renders, events are
            // taken as they come: input that finds the image up to date (the start of a drag, a
            // key) begins the next frame at once instead of up to a frame period later; during a
            // drag, the coarse previews pace the frames. Idle, events wait for the blocking wait
            // above, which answers them at once.
            wait_for_next_frame(model, frame_start, FramePacing{}, [&] {
                if (app.idle()) return false;
                glfwPollEvents();
                polled_while_waiting = true;  // events taken: the next frame must not block for more
                return input_arrived && std::chrono::steady_clock::now() - frame_start >= min_frame_interval &&
                       coarse_preview(model.driver()) == CoarsePreview::none;
            });
        }
        glfwSetWindowUserPointer(window, nullptr);
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window);
    glfwTerminate();
    return code;
}

}  // namespace

int main(int argc, char** argv) { return view_main(argc, argv, run_window); }
