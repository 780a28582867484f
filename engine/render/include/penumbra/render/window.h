// Glfw and Window: a GLFW 3.3 window (no client API) and its VkSurfaceKHR.
//
// Order of creation for a windowed renderer: Glfw, Instance (with Glfw::instance_extensions),
// Window (creates the surface), Device (with the surface, so the queue can present),
// WindowTarget (swapchain), Renderer. Destroy in reverse order.
//
// Threading: GLFW requires the main thread for everything here (creation, events, sizes).
#pragma once

#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "penumbra/render/instance.h"

struct GLFWwindow;

namespace penumbra::render {

class Glfw {
 public:
  // Throws std::runtime_error with GLFW's reason when it cannot start (e.g. no X display).
  Glfw();
  ~Glfw();
  Glfw(const Glfw&) = delete;
  Glfw& operator=(const Glfw&) = delete;

  // Whether a display is advertised ($DISPLAY or $WAYLAND_DISPLAY); cheap, starts nothing.
  static bool display_available();
  // The instance extensions GLFW needs for surfaces (VK_KHR_surface + the platform's).
  std::vector<std::string> instance_extensions() const;
};

class Window {
 public:
  Window(Glfw& glfw, Instance& instance, int width, int height, const std::string& title);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  GLFWwindow* glfw() const { return window_; }
  VkSurfaceKHR surface() const { return surface_; }
  // Framebuffer size in pixels; {0, 0} while minimised.
  VkExtent2D framebuffer_extent() const;
  bool minimised() const;
  bool should_close() const;
  bool escape_pressed() const;
  void request_close();
  void poll_events();
  // Asks the window system for a new client size (takes effect after poll_events()).
  void set_size(int width, int height);
  void set_title(const std::string& title);

 private:
  Instance* instance_;
  GLFWwindow* window_ = nullptr;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
};

}  // namespace penumbra::render
