#include "app/window/app_window.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "engine/io/png_write.h"
#include "render/gl_api.h"
#include "render/render_error.h"

namespace ps::window {

namespace {

// Mesa's software rasteriser (llvmpipe: no GPU, or xvfb) draws with as many threads as there are
// cores, and on a small machine those preempt the physics thread: on 2 cores under xvfb the
// biopsy script's ticks ran over their 2 ms period 94-142 times in 1500 with the default, 18-28
// with one thread. One core is left to the physics; a GPU driver ignores the variable, and a
// value the user set is kept.
void leave_a_core_to_the_physics() {
  const unsigned cores = std::thread::hardware_concurrency();
  const std::string n = std::to_string(cores > 2 ? cores - 1 : 1);
  setenv("LP_NUM_THREADS", n.c_str(), 0);
}

}  // namespace

std::unique_ptr<AppWindow> AppWindow::open(const char* title, int width, int height, const char* no_display) {
  leave_a_core_to_the_physics();
  glfwSetErrorCallback([](int code, const char* msg) { std::fprintf(stderr, "GLFW error %d: %s\n", code, msg); });
  if (!glfwInit()) {
    std::fprintf(stderr, "%s\n", no_display);
    return nullptr;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  GLFWwindow* win = glfwCreateWindow(width, height, title, nullptr, nullptr);
  if (!win) {
    glfwTerminate();
    std::fprintf(stderr, "error: cannot create an OpenGL 3.3 core window\n");
    return nullptr;
  }
  glfwMakeContextCurrent(win);
  glfwSwapInterval(1);
  try {
    gl::load([](const char* n) { return reinterpret_cast<void*>(glfwGetProcAddress(n)); });
  } catch (const render::RenderError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    glfwDestroyWindow(win);
    glfwTerminate();
    return nullptr;
  }
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(win, true);
  ImGui_ImplOpenGL3_Init("#version 330");
  return std::unique_ptr<AppWindow>(new AppWindow(win));
}

AppWindow::~AppWindow() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(win_);
  glfwTerminate();
}

bool AppWindow::should_close() const { return glfwWindowShouldClose(win_); }
void AppWindow::close() { glfwSetWindowShouldClose(win_, GLFW_TRUE); }
void AppWindow::poll_events() { glfwPollEvents(); }

void AppWindow::new_backend_frame() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
}

void AppWindow::clear_framebuffer(int& width_px, int& height_px) {
  glfwGetFramebufferSize(win_, &width_px, &height_px);
  gl::api.BindFramebuffer(GL_FRAMEBUFFER, 0);
  gl::api.Viewport(0, 0, width_px, height_px);
  gl::api.ClearColor(0.05f, 0.05f, 0.06f, 1.0f);
  gl::api.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void AppWindow::draw_imgui() { ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData()); }
void AppWindow::swap() { glfwSwapBuffers(win_); }

bool write_framebuffer_png(const std::string& path, int fbw, int fbh) {
  std::vector<uint8_t> rgba(4 * static_cast<size_t>(fbw) * fbh), rgb(3 * static_cast<size_t>(fbw) * fbh);
  gl::api.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl::api.ReadPixels(0, 0, fbw, fbh, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  for (int y = 0; y < fbh; ++y)
    for (int x = 0; x < fbw; ++x)
      for (int c = 0; c < 3; ++c) rgb[3 * (static_cast<size_t>(y) * fbw + x) + c] = rgba[4 * (static_cast<size_t>(fbh - 1 - y) * fbw + x) + c];
  try {
    ps::write_png_atomic(path, fbw, fbh, 3, rgb.data());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return false;
  }
  return true;
}

}  // namespace ps::window
