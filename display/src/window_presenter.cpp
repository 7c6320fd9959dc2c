// Presentation in GLFW windows: one fullscreen window per chosen monitor (monitors layout) or one
// window (cross). Each window has its own OpenGL 3.3 core context and QuadRenderer; contexts are
// not shared, so each window only uploads the faces it shows.
#include <GLFW/glfw3.h>

#include <fmt/format.h>
#include <string>
#include <vector>

#include "compose.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"

namespace holo::display {

namespace {

std::string& lastGlfwError() {
  static std::string message;
  return message;
}

void onGlfwError(int code, const char* description) {
  lastGlfwError() = fmt::format("{} (GLFW error {:#x})", description ? description : "", code);
}

void onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int /*mods*/) {
  if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(window, GLFW_TRUE);
}

// Leaves no context current when a presenter call ends, so the thread stays free for another
// presenter or API (Mesa refuses a GLX context current while an EGL one is, and vice versa).
struct ReleaseContextOnExit {
  ReleaseContextOnExit() = default;
  ~ReleaseContextOnExit() { glfwMakeContextCurrent(nullptr); }
  ReleaseContextOnExit(const ReleaseContextOnExit&) = delete;
  ReleaseContextOnExit& operator=(const ReleaseContextOnExit&) = delete;
};

struct Window {
  GLFWwindow* handle = nullptr;
  int output = 0;
  std::unique_ptr<QuadRenderer> renderer;
};

class WindowPresenter final : public QuadViewPresenter {
 public:
  explicit WindowPresenter(const DisplayConfig& config) : config_(config) {
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit())
      throw Error("display: cannot open windows (" + lastGlfwError() +
                  "); is DISPLAY set? Use --headless on a machine without a screen");
    try {
      openWindows();
    } catch (...) {
      closeWindows();
      glfwTerminate();
      throw;
    }
  }
  ~WindowPresenter() override {
    closeWindows();
    glfwTerminate();
  }

  void present(const FaceImages& faces, const FaceImages* coverage) override {
    crops_ = chooseCrops(config_, faces, coverage, crops_);
    const ReleaseContextOnExit release;
    for (Window& window : windows_) {
      glfwMakeContextCurrent(window.handle);
      for (int f = 0; f < kFaceCount; ++f) {
        const cv::Mat& face = faces[static_cast<std::size_t>(f)];
        if (!face.empty() && outputOf(f) == window.output) window.renderer->upload(f, face);
      }
      draw(window);
      glfwSwapBuffers(window.handle);
    }
    glfwPollEvents();
  }

  // Draws the last frame again into each back buffer and reads it: what the windows show.
  cv::Mat readBack() override {
    std::vector<cv::Mat> outputs;
    cv::Size cell(0, 0);
    const ReleaseContextOnExit release;
    for (Window& window : windows_) {
      glfwMakeContextCurrent(window.handle);
      draw(window);
      glReadBuffer(GL_BACK);
      const cv::Size size = framebufferSize(window);
      outputs.push_back(readPixelsBgr({0, 0, size.width, size.height}, size.height));
      cell = {std::max(cell.width, size.width), std::max(cell.height, size.height)};
    }
    if (outputs.size() == 1) return outputs.front();
    cv::Mat sheet(2 * cell.height, 2 * cell.width, CV_8UC3, cv::Scalar::all(0));
    for (std::size_t k = 0; k < outputs.size(); ++k) {
      const int x = static_cast<int>(k % 2) * cell.width, y = static_cast<int>(k / 2) * cell.height;
      outputs[k].copyTo(sheet(cv::Rect(x, y, outputs[k].cols, outputs[k].rows)));
    }
    return sheet;
  }

  bool isOpen() override {
    glfwPollEvents();
    for (const Window& window : windows_)
      if (glfwWindowShouldClose(window.handle)) return false;
    return true;
  }
  const DisplayConfig& config() const override { return config_; }
  cv::Size outputSize(int output) const override {
    for (const Window& window : windows_)
      if (window.output == output) return framebufferSize(window);
    return config_.output_size;
  }
  const std::array<cv::Rect2f, kFaceCount>& lastCrops() const override { return crops_; }

 private:
  int outputOf(int face) const { return config_.layout == LayoutKind::Monitors ? face : 0; }

  static cv::Size framebufferSize(const Window& window) {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window.handle, &w, &h);
    return {w, h};
  }

  void draw(Window& window) {
    const cv::Size size = framebufferSize(window);
    drawOutput(*window.renderer, config_, window.output, {0, 0}, size, size.height, crops_);
  }

  void openWindows() {
    const ReleaseContextOnExit release;
    int monitor_count = 0;
    GLFWmonitor** monitors = glfwGetMonitors(&monitor_count);
    for (int output = 0; output < outputCount(config_.layout); ++output) {
      const FaceSettings& face = config_.faces[static_cast<std::size_t>(output)];
      const int index = face.monitor >= 0 ? face.monitor : output;
      GLFWmonitor* monitor = nullptr;
      cv::Size size = config_.output_size;
      if (config_.fullscreen) {
        if (index >= monitor_count)
          throw InputError(config_.source, fmt::format("display.faces[{}].monitor", output),
                           fmt::format("a connected monitor index below {}", monitor_count),
                           std::to_string(index));
        monitor = monitors[index];
        const GLFWvidmode* mode = glfwGetVideoMode(monitor);
        size = {mode->width, mode->height};
      }
      glfwDefaultWindowHints();
      glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
      glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
      glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
      glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
      glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
      glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);  // shown after it is placed
      const std::string title = fmt::format("holopyramid {} {}", layoutName(config_.layout), output);
      Window window;
      window.output = output;
      window.handle = glfwCreateWindow(size.width, size.height, title.c_str(), monitor, nullptr);
      if (!window.handle) throw Error("display: cannot open a window: " + lastGlfwError());
      windows_.push_back(std::move(window));
      Window& opened = windows_.back();
      if (!monitor) {
        const cv::Point origin = outputOrigin(config_, output);
        glfwSetWindowPos(opened.handle, origin.x, origin.y);
      }
      glfwSetKeyCallback(opened.handle, onKey);
      glfwShowWindow(opened.handle);
      glfwMakeContextCurrent(opened.handle);
      glfwSwapInterval(1);
      opened.renderer = std::make_unique<QuadRenderer>();
      HOLO_LOG_INFO("display: output {} in a {}x{} {} window ({})", output, size.width, size.height,
                    monitor ? "fullscreen" : "plain",
                    reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    }
  }

  void closeWindows() {
    const ReleaseContextOnExit release;
    for (Window& window : windows_) {
      glfwMakeContextCurrent(window.handle);
      window.renderer.reset();
      glfwDestroyWindow(window.handle);
    }
    windows_.clear();
  }

  DisplayConfig config_;
  std::vector<Window> windows_;
  std::array<cv::Rect2f, kFaceCount> crops_{};
};

}  // namespace

std::unique_ptr<QuadViewPresenter> makeWindowPresenter(const DisplayConfig& config) {
  return std::make_unique<WindowPresenter>(config);
}

}  // namespace holo::display
