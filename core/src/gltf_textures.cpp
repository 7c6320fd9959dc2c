#include "gltf_textures.hpp"

#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/core/gltf_limits.hpp"
#include "holo/core/log.hpp"
#include "holo/core/stats.hpp"

namespace holo::gltf_detail {

namespace {

// A decoded glTF image as the 8-bit BGR (or BGRA, where some alpha is below 255) holo::Texture
// holds; empty when tinygltf left no usable pixels.
cv::Mat decodeImage(const tinygltf::Image& image) {
  if (image.image.empty() || image.width <= 0 || image.height <= 0) return {};
  const int channels = image.component;
  if (channels < 1 || channels > 4) return {};
  cv::Mat raw;
  if (image.bits == 16) {
    cv::Mat wide(image.height, image.width, CV_16UC(channels),
                 const_cast<unsigned char*>(image.image.data()));
    wide.convertTo(raw, CV_8U, 1.0 / 257.0);
  } else {
    raw = cv::Mat(image.height, image.width, CV_8UC(channels), const_cast<unsigned char*>(image.image.data()))
              .clone();
  }
  cv::Mat out;
  switch (channels) {
    case 1:
      cv::cvtColor(raw, out, cv::COLOR_GRAY2BGR);
      break;
    case 2: {
      cv::Mat gray;
      cv::extractChannel(raw, gray, 0);
      cv::cvtColor(gray, out, cv::COLOR_GRAY2BGR);
      break;
    }
    case 3:
      cv::cvtColor(raw, out, cv::COLOR_RGB2BGR);
      break;
    default: {
      // An opaque texture drops its alpha.
      cv::Mat alpha;
      cv::extractChannel(raw, alpha, 3);
      double lowest = 0;
      cv::minMaxLoc(alpha, &lowest);
      cv::cvtColor(raw, out, lowest >= 255.0 ? cv::COLOR_RGBA2BGR : cv::COLOR_RGBA2BGRA);
      break;
    }
  }
  return out;
}

TextureWrap wrapMode(int gl_wrap) {
  switch (gl_wrap) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
      return TextureWrap::ClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
      return TextureWrap::MirroredRepeat;
    default:
      return TextureWrap::Repeat;
  }
}

// glTF leaves unset filters to the viewer: bilinear with blended mips, the one that never aliases.
TextureSampler samplerFrom(const tinygltf::Sampler& s) {
  TextureSampler out;
  out.wrap_u = wrapMode(s.wrapS);
  out.wrap_v = wrapMode(s.wrapT);
  out.magnify_linear = s.magFilter != TINYGLTF_TEXTURE_FILTER_NEAREST;
  switch (s.minFilter) {
    case TINYGLTF_TEXTURE_FILTER_NEAREST:
    case TINYGLTF_TEXTURE_FILTER_LINEAR:
      out.use_mips = false;
      out.minify_linear = s.minFilter == TINYGLTF_TEXTURE_FILTER_LINEAR;
      break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST:
    case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST:
      out.blend_mips = false;
      out.minify_linear = s.minFilter == TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST;
      break;
    case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR:
      out.minify_linear = false;
      break;
    default:
      break;
  }
  return out;
}

}  // namespace

bool decodeTexture(tinygltf::Image* image, const int image_index, std::string* err, std::string*, int, int,
                   const unsigned char* bytes, int size, void*) {
  const std::string which = "image " + std::to_string(image_index);
  // glTF allows PNG and JPEG; OpenCV would also try TIFF, WebP, PNM and more, so only those two
  // are handed to it.
  const bool png = size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0;
  const bool jpeg = size >= 3 && std::memcmp(bytes, "\xff\xd8\xff", 3) == 0;
  if (!png && !jpeg) {
    if (err) *err += which + ": not a PNG or JPEG image\n";
    return false;
  }
  cv::Mat decoded;
  try {
    decoded =
        cv::imdecode(cv::Mat(1, size, CV_8UC1, const_cast<unsigned char*>(bytes)), cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    if (err) *err += which + ": " + e.what() + "\n";
    return false;
  }
  if (decoded.empty()) {
    if (err) *err += which + ": not a PNG or JPEG image OpenCV can decode\n";
    return false;
  }
  if (decoded.cols > kMaxGltfTextureSide || decoded.rows > kMaxGltfTextureSide) {
    if (err)
      *err += which + " is " + std::to_string(decoded.cols) + "x" + std::to_string(decoded.rows) +
              ", expected at most " + std::to_string(kMaxGltfTextureSide) + " pixels a side\n";
    return false;
  }
  if (decoded.depth() != CV_8U && decoded.depth() != CV_16U) decoded.convertTo(decoded, CV_8U);
  cv::Mat rgb;  // glTF images are RGB(A); OpenCV decodes to BGR(A)
  switch (decoded.channels()) {
    case 3:
      cv::cvtColor(decoded, rgb, cv::COLOR_BGR2RGB);
      break;
    case 4:
      cv::cvtColor(decoded, rgb, cv::COLOR_BGRA2RGBA);
      break;
    default:
      rgb = decoded;
  }
  if (!rgb.isContinuous()) rgb = rgb.clone();
  image->width = rgb.cols;
  image->height = rgb.rows;
  image->component = rgb.channels();
  image->bits = rgb.depth() == CV_16U ? 16 : 8;
  image->pixel_type =
      rgb.depth() == CV_16U ? TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image->image.assign(rgb.data, rgb.data + rgb.total() * rgb.elemSize());
  return true;
}

TextureTable::TextureTable(const tinygltf::Model& gltf, const std::string& file,
                           std::vector<Texture>& textures)
    : gltf_(gltf), file_(file), textures_(textures), built_(gltf.textures.size(), {-1, -1}) {}

int TextureTable::index(int gltf_texture, TextureEncoding encoding) {
  if (gltf_texture < 0 || gltf_texture >= static_cast<int>(gltf_.textures.size()))
    throw InputError(file_, "textures", "a texture index < " + std::to_string(gltf_.textures.size()),
                     std::to_string(gltf_texture));
  auto& slot = built_[static_cast<std::size_t>(gltf_texture)][encoding == TextureEncoding::Srgb];
  if (slot >= 0) return slot;
  const auto& texture = gltf_.textures[static_cast<std::size_t>(gltf_texture)];
  const int source = texture.source;
  if (source < 0 || source >= static_cast<int>(gltf_.images.size())) {
    stats::add("glTF/Textures ignored");
    HOLO_LOG_WARN("{}: textures[{}] has no image this build decodes (source {}): texture ignored", file_,
                  gltf_texture, source);
    return -1;
  }
  cv::Mat decoded = decodeImage(gltf_.images[static_cast<std::size_t>(source)]);
  if (decoded.empty()) {
    stats::add("glTF/Textures ignored");
    HOLO_LOG_WARN("{}: images[{}]: could not decode, texture ignored", file_, source);
    return -1;
  }
  TextureSampler sampler;
  if (texture.sampler >= 0) {
    if (texture.sampler >= static_cast<int>(gltf_.samplers.size()))
      throw InputError(file_, "textures[" + std::to_string(gltf_texture) + "].sampler",
                       "a sampler index < " + std::to_string(gltf_.samplers.size()),
                       std::to_string(texture.sampler));
    sampler = samplerFrom(gltf_.samplers[static_cast<std::size_t>(texture.sampler)]);
  }
  slot = static_cast<int>(textures_.size());
  textures_.emplace_back(std::move(decoded), sampler, encoding);
  return slot;
}

}  // namespace holo::gltf_detail
