// Draws face images as transformed quads (private to the display module). One instance per GL
// context; every call needs that context current. The vertex shader applies a FacePlacement's
// unit_to_output matrix, so rotation, mirroring, offset and scale happen on the GPU; the fragment
// shader encodes linear HDR faces to sRGB after exposure (8-bit faces pass through).
#pragma once

#include <array>
#include <opencv2/core.hpp>

#include "gl.hpp"
#include "holo/display/layout.hpp"

namespace holo::display {

class QuadRenderer {
 public:
  QuadRenderer();
  ~QuadRenderer();
  QuadRenderer(const QuadRenderer&) = delete;
  QuadRenderer& operator=(const QuadRenderer&) = delete;

  // Uploads `image` (CV_8UC3 sRGB or CV_32FC3 linear, BGR) as the texture of face `face`.
  void upload(int face, const cv::Mat& image);
  // Makes the output at `origin` (top-left, pixels) of size `output` the drawing target inside
  // a framebuffer `framebuffer_height` pixels tall and clears it to black.
  void beginOutput(cv::Point origin, cv::Size output, int framebuffer_height);
  // Draws the uploaded face with `placement`, sampling the crop `crop` (image pixels).
  void drawFace(const FacePlacement& placement, cv::Rect2f crop, float exposure);

 private:
  struct Texture {
    GLuint id = 0;
    cv::Size size;
    int type = -1;
  };
  GLuint program_ = 0;
  GLuint vao_ = 0;
  GLuint vbo_ = 0;
  GLint u_unit_to_output_ = -1, u_output_size_ = -1, u_uv_rect_ = -1, u_linear_ = -1, u_exposure_ = -1;
  std::array<Texture, kFaceCount> textures_{};
  cv::Size output_;
};

// A linear HDR face with NaN -> 0, +Inf -> FLT_MAX (saturates) and negatives -> 0, as uploaded.
cv::Mat finiteLinearFace(const cv::Mat& image);

// Reads `region` (top-left origin) of the current read framebuffer, `framebuffer_height` pixels
// tall, into a CV_8UC3 BGR image with row 0 at the top.
cv::Mat readPixelsBgr(cv::Rect region, int framebuffer_height);

}  // namespace holo::display
