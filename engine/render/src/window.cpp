#include "penumbra/render/window.h"

#include <cstdlib>
#include <stdexcept>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "penumbra/render/vk_check.h"

namespace penumbra::render {
namespace {
std::string glfw_error() {
  const char* text = nullptr;
  const int code = glfwGetError(&text);
  if (code == GLFW_NO_ERROR) return "no GLFW error reported";
  return text ? text : "GLFW error " + std::to_string(code);
}
}  // namespace

Glfw::Glfw() {
  if (glfwInit() != GLFW_TRUE) throw std::runtime_error("glfwInit: " + glfw_error());
  if (glfwVulkanSupported() != GLFW_TRUE) {
    glfwTerminate();
    throw std::runtime_error("GLFW finds no Vulkan loader");
  }
}

Glfw::~Glfw() {
  glfwTerminate();
}

bool Glfw::display_available() {
  const char* x = std::getenv("DISPLAY");
  const char* wl = std::getenv("WAYLAND_DISPLAY");
  return (x != nullptr && *x != '\0') || (wl != nullptr && *wl != '\0');
}

std::vector<std::string> Glfw::instance_extensions() const {
  std::uint32_t n = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&n);
  if (names == nullptr)
    throw std::runtime_error("glfwGetRequiredInstanceExtensions: " + glfw_error());
  return {names, names + n};
}

Window::Window(Glfw&, Instance& instance, int width, int height, const std::string& title)
    : instance_(&instance) {
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (window_ == nullptr) throw std::runtime_error("glfwCreateWindow: " + glfw_error());
  const VkResult r = glfwCreateWindowSurface(instance.handle(), window_, nullptr, &surface_);
  if (r != VK_SUCCESS) {
    glfwDestroyWindow(window_);
    throw VulkanError("glfwCreateWindowSurface", r);
  }
}

Window::~Window() {
  if (surface_ != VK_NULL_HANDLE) vkDestroySurfaceKHR(instance_->handle(), surface_, nullptr);
  if (window_ != nullptr) glfwDestroyWindow(window_);
}

VkExtent2D Window::framebuffer_extent() const {
  if (minimised()) return {0, 0};
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return {static_cast<std::uint32_t>(w > 0 ? w : 0), static_cast<std::uint32_t>(h > 0 ? h : 0)};
}

bool Window::minimised() const {
  return glfwGetWindowAttrib(window_, GLFW_ICONIFIED) != 0;
}
bool Window::escape_pressed() const {
  return glfwGetKey(window_, GLFW_KEY_ESCAPE) == GLFW_PRESS;
}
bool Window::should_close() const {
  return glfwWindowShouldClose(window_) != 0;
}
void Window::request_close() {
  glfwSetWindowShouldClose(window_, GLFW_TRUE);
}
void Window::poll_events() {
  glfwPollEvents();
}
void Window::set_size(int width, int height) {
  glfwSetWindowSize(window_, width, height);
}
void Window::set_title(const std::string& title) {
  glfwSetWindowTitle(window_, title.c_str());
}

}  // namespace penumbra::render
