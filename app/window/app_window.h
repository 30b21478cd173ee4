// The platform window the trainee window and the scenario editor share: a GLFW window with an
// OpenGL 3.3 core context (4x multisampling, vsync), the GL entry points of render/gl_api.h loaded
// from it, and a Dear ImGui context with its GLFW and OpenGL 3 backends. The app (its panels,
// views and input) stays with the caller; this holds only what every window does the same.
#pragma once
#include <memory>
#include <string>

struct GLFWwindow;

namespace ps::window {

class AppWindow {
 public:
  // Opens the window, loads GL and starts ImGui. On failure prints one line to stderr
  // ("error: ..."; no_display: the line when GLFW cannot start, e.g. no display) and returns null.
  static std::unique_ptr<AppWindow> open(const char* title, int width, int height, const char* no_display);
  // ImGui's backends and context shut down, the window destroyed, GLFW terminated.
  ~AppWindow();
  AppWindow(const AppWindow&) = delete;
  AppWindow& operator=(const AppWindow&) = delete;

  GLFWwindow* glfw() const { return win_; }
  bool should_close() const;
  void close();  // the loop ends after this frame
  void poll_events();
  // ImGui's backends start a frame (the caller then feeds its own input and calls ImGui::NewFrame)
  void new_backend_frame();
  // The framebuffer in pixels; binds the default framebuffer over all of it and clears it to the
  // windows' background colour.
  void clear_framebuffer(int& width_px, int& height_px);
  void draw_imgui();  // ImGui's draw data of this frame (after ImGui::Render)
  void swap();

 private:
  explicit AppWindow(GLFWwindow* win) : win_(win) {}
  GLFWwindow* win_ = nullptr;
};

// Reads the default framebuffer (width x height px) back and writes it as an RGB PNG, atomically;
// false (the error printed) when the file cannot be written.
bool write_framebuffer_png(const std::string& path, int width_px, int height_px);

}  // namespace ps::window
