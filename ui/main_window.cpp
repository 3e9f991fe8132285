// caustica-view: the preview in a GLFW window (OpenGL 3.3 core through libOpenGL).
// `caustica view` execs this when there is a DISPLAY and no --headless.
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
        const auto frame_time = std::chrono::microseconds(16667);  // Xvfb does not wait for vsync
        auto next_frame = std::chrono::steady_clock::now();
        while (!glfwWindowShouldClose(window) && !app.quit_requested()) {
            if (app.idle() && !args.scripted()) glfwWaitEventsTimeout(0.25);  // file changes are polled
            else glfwPollEvents();
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
            app.draw(glm::vec2(width, height), fb_width, fb_height);
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            if (args.scripted() && run.done(model)) {
                if (!args.snapshot.empty()) write_snapshot(args.snapshot, read_back_buffer(fb_width, fb_height), fb_width, fb_height, "glfw");
                if (run.timed_out()) {
                    std::fprintf(stderr, "caustica view: gave up waiting for the render\n");
                    code = 1;
                }
                break;
            }
            glfwSwapBuffers(window);
            next_frame += frame_time;
            const auto now = std::chrono::steady_clock::now();
            if (next_frame > now) wait_for_frame(model, next_frame);
            else next_frame = now;
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
