#include "quad_renderer.hpp"

#include <fmt/format.h>
#include <glm/gtc/type_ptr.hpp>
#include <limits>

#include "holo/core/error.hpp"

namespace holo::display {

namespace gl {
void check(const char* what) {
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) throw Error(fmt::format("OpenGL error {:#06x} in {}", error, what));
}
}  // namespace gl

namespace {

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec2 unit;   // corner of the unit quad, (u, v) in [0, 1]^2, v down
uniform mat3 unit_to_output;         // unit crop coordinates -> output pixels (+y down)
uniform vec2 output_size;            // pixels
uniform vec4 uv_rect;                // crop in texture coordinates: u0, v0, u1, v1
out vec2 uv;
void main() {
  vec2 p = (unit_to_output * vec3(unit, 1.0)).xy;
  gl_Position = vec4(p.x / output_size.x * 2.0 - 1.0, 1.0 - p.y / output_size.y * 2.0, 0.0, 1.0);
  uv = mix(uv_rect.xy, uv_rect.zw, unit);
}
)";

// Texture row 0 is the image's top row, so v = 0 samples the top, matching the unit quad.
constexpr const char* kFragmentShader = R"(#version 330 core
in vec2 uv;
out vec4 colour;
uniform sampler2D face;
uniform int linear_input;  // 1: linear HDR radiance, encode to sRGB; 0: already sRGB
uniform float exposure;
vec3 encodeSrgb(vec3 c) {
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}
void main() {
  vec3 c = texture(face, uv).rgb;
  if (linear_input == 1) {
    c = mix(c, vec3(0.0), isnan(c));  // upload already repaired NaN (finiteLinearFace); never show one
    c = encodeSrgb(clamp(c * exposure, 0.0, 1.0));
  }
  colour = vec4(c, 1.0);
}
)";

GLuint compile(GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw Error(std::string("display: shader does not compile: ") + log);
  }
  return shader;
}

}  // namespace

QuadRenderer::QuadRenderer() {
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    char log[2048] = {};
    glGetProgramInfoLog(program_, sizeof log, nullptr, log);
    glDeleteProgram(program_);
    throw Error(std::string("display: shader program does not link: ") + log);
  }
  u_unit_to_output_ = glGetUniformLocation(program_, "unit_to_output");
  u_output_size_ = glGetUniformLocation(program_, "output_size");
  u_uv_rect_ = glGetUniformLocation(program_, "uv_rect");
  u_linear_ = glGetUniformLocation(program_, "linear_input");
  u_exposure_ = glGetUniformLocation(program_, "exposure");

  static constexpr float kUnitQuad[] = {0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f, 1.0f, 1.0f};
  glGenVertexArrays(1, &vao_);
  glGenBuffers(1, &vbo_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glBufferData(GL_ARRAY_BUFFER, sizeof kUnitQuad, kUnitQuad, GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), nullptr);
  glBindVertexArray(0);
  for (Texture& texture : textures_) glGenTextures(1, &texture.id);
  gl::check("creating the quad renderer");
}

QuadRenderer::~QuadRenderer() {
  for (Texture& texture : textures_) glDeleteTextures(1, &texture.id);
  glDeleteBuffers(1, &vbo_);
  glDeleteVertexArrays(1, &vao_);
  glDeleteProgram(program_);
}

cv::Mat finiteLinearFace(const cv::Mat& image) {
  // Bilinear filtering computes a + t * (b - a): a NaN or infinite texel would poison its
  // neighbours even at weight 0, so the texture holds repaired values (negatives clamp to 0
  // later anyway).
  cv::Mat repaired = image.clone();
  cv::patchNaNs(repaired, 0.0);
  cv::min(repaired, std::numeric_limits<float>::max(), repaired);
  cv::max(repaired, 0.0, repaired);
  return repaired;
}

void QuadRenderer::upload(int face, const cv::Mat& input) {
  if (input.type() != CV_8UC3 && input.type() != CV_32FC3)
    throw Error("display: face " + std::to_string(face) + " must be CV_8UC3 or CV_32FC3");
  Texture& texture = textures_.at(static_cast<std::size_t>(face));
  const bool is_float = input.depth() == CV_32F;
  const cv::Mat image = is_float ? finiteLinearFace(input) : input;
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, texture.id);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, static_cast<GLint>(image.step[0] / image.elemSize()));
  const GLenum type = is_float ? GL_FLOAT : GL_UNSIGNED_BYTE;
  if (texture.size != image.size() || texture.type != image.type()) {
    glTexImage2D(GL_TEXTURE_2D, 0, is_float ? GL_RGB32F : GL_RGB8, image.cols, image.rows, 0, GL_BGR, type,
                 image.data);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    texture.size = image.size();
    texture.type = image.type();
  } else {
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, image.cols, image.rows, GL_BGR, type, image.data);
  }
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  gl::check("uploading a face texture");
}

void QuadRenderer::beginOutput(cv::Point origin, cv::Size output, int framebuffer_height) {
  const GLint y = framebuffer_height - origin.y - output.height;  // GL's origin is bottom-left
  glViewport(origin.x, y, output.width, output.height);
  glEnable(GL_SCISSOR_TEST);
  glScissor(origin.x, y, output.width, output.height);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  glDisable(GL_SCISSOR_TEST);
  output_ = output;
}

void QuadRenderer::drawFace(const FacePlacement& placement, cv::Rect2f crop, float exposure) {
  const Texture& texture = textures_.at(static_cast<std::size_t>(placement.face));
  if (texture.type < 0)
    throw Error("display: face " + std::to_string(placement.face) + " drawn before upload");
  const float w = static_cast<float>(texture.size.width);
  const float h = static_cast<float>(texture.size.height);
  glUseProgram(program_);
  glUniformMatrix3fv(u_unit_to_output_, 1, GL_FALSE, glm::value_ptr(placement.unit_to_output));
  glUniform2f(u_output_size_, static_cast<float>(output_.width), static_cast<float>(output_.height));
  glUniform4f(u_uv_rect_, crop.x / w, crop.y / h, (crop.x + crop.width) / w, (crop.y + crop.height) / h);
  glUniform1i(u_linear_, texture.type == CV_32FC3 ? 1 : 0);
  glUniform1f(u_exposure_, exposure);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, texture.id);
  glBindVertexArray(vao_);
  glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  glBindVertexArray(0);
  gl::check("drawing a face");
}

cv::Mat readPixelsBgr(cv::Rect region, int framebuffer_height) {
  cv::Mat image(region.height, region.width, CV_8UC3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(region.x, framebuffer_height - region.y - region.height, region.width, region.height, GL_BGR,
               GL_UNSIGNED_BYTE, image.data);
  gl::check("reading pixels back");
  cv::flip(image, image, 0);  // GL rows run bottom-up
  return image;
}

}  // namespace holo::display
