// Headless presentation: an OpenGL 3.3 core context from EGL on Mesa's surfaceless platform
// (EGL_MESA_platform_surfaceless: no window system, no pbuffer, no GPU needed; llvmpipe renders
// on the CPU) drawing into a framebuffer object the size of the canvas.
#define EGL_NO_X11 1  // keep Xlib's macros (None, Status, ...) out of this file
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <fmt/format.h>

#include "compose.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"

namespace holo::display {

namespace {

[[noreturn]] void eglFail(const char* what) {
  throw Error(fmt::format("display: headless OpenGL unavailable: {} failed (EGL error {:#06x})", what,
                          static_cast<unsigned>(eglGetError())));
}

class EglContext {
 public:
  EglContext() {
    const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client_extensions ||
        std::string(client_extensions).find("EGL_MESA_platform_surfaceless") == std::string::npos)
      throw Error("display: headless OpenGL unavailable: EGL lacks EGL_MESA_platform_surfaceless");
    const auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display) eglFail("eglGetProcAddress(eglGetPlatformDisplayEXT)");
    display_ = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display_ == EGL_NO_DISPLAY) eglFail("eglGetPlatformDisplayEXT");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display_, &major, &minor)) eglFail("eglInitialize");
    if (!eglBindAPI(EGL_OPENGL_API)) eglFail("eglBindAPI(OpenGL)");
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 3,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 3,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    // EGL_KHR_no_config_context: no surface will ever be bound, so no config is needed.
    context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context_ == EGL_NO_CONTEXT) {
      eglTerminate(display_);
      eglFail("eglCreateContext(OpenGL 3.3 core)");
    }
  }
  ~EglContext() {
    release();
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;
  void makeCurrent() {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) eglFail("eglMakeCurrent");
  }
  void release() { eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT); }

  // Current for one call of the presenter, released after it: the thread stays free for another
  // API (Mesa refuses a GLX context current while an EGL one is), and for another presenter.
  class Scope {
   public:
    explicit Scope(EglContext& context) : context_(context) { context_.makeCurrent(); }
    ~Scope() { context_.release(); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    EglContext& context_;
  };

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

class HeadlessPresenter final : public QuadViewPresenter {
 public:
  explicit HeadlessPresenter(const DisplayConfig& config) : config_(config), canvas_(canvasSize(config)) {
    const EglContext::Scope current(context_);
    HOLO_LOG_DEBUG("display: headless OpenGL {} on {}",
                   reinterpret_cast<const char*>(glGetString(GL_VERSION)),
                   reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
    renderer_ = std::make_unique<QuadRenderer>();
    glGenFramebuffers(1, &framebuffer_);
    glGenRenderbuffers(1, &colour_);
    glBindRenderbuffer(GL_RENDERBUFFER, colour_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, canvas_.width, canvas_.height);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw Error(fmt::format("display: offscreen framebuffer of {}x{} is incomplete", canvas_.width,
                              canvas_.height));
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    gl::check("creating the offscreen framebuffer");
    crops_.fill(cv::Rect2f());
  }
  ~HeadlessPresenter() override {
    const EglContext::Scope current(context_);
    renderer_.reset();
    glDeleteRenderbuffers(1, &colour_);
    glDeleteFramebuffers(1, &framebuffer_);
  }

  void present(const FaceImages& faces, const FaceImages* coverage) override {
    crops_ = chooseCrops(config_, faces, coverage, crops_);
    const EglContext::Scope current(context_);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    for (int f = 0; f < kFaceCount; ++f)
      if (!faces[static_cast<std::size_t>(f)].empty())
        renderer_->upload(f, faces[static_cast<std::size_t>(f)]);
    for (int output = 0; output < outputCount(config_.layout); ++output)
      drawOutput(*renderer_, config_, output, outputOrigin(config_, output), config_.output_size,
                 canvas_.height, crops_);
  }

  cv::Mat readBack() override {
    const EglContext::Scope current(context_);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    return readPixelsBgr({0, 0, canvas_.width, canvas_.height}, canvas_.height);
  }

  bool isOpen() override { return true; }
  const DisplayConfig& config() const override { return config_; }
  const std::array<cv::Rect2f, kFaceCount>& lastCrops() const override { return crops_; }

 private:
  DisplayConfig config_;
  cv::Size canvas_;
  EglContext context_;
  std::unique_ptr<QuadRenderer> renderer_;
  GLuint framebuffer_ = 0;
  GLuint colour_ = 0;
  std::array<cv::Rect2f, kFaceCount> crops_{};
};

}  // namespace

std::unique_ptr<QuadViewPresenter> makeHeadlessPresenter(const DisplayConfig& config) {
  return std::make_unique<HeadlessPresenter>(config);
}

}  // namespace holo::display
