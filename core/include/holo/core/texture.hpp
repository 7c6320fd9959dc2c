// Material textures as glTF states them: an 8-bit image with its mip chain and its sampler, and
// filtered lookups whose mip level follows the footprint of the pixel being shaded, so a relic
// seen small on a 320x320 view does not alias.
//
// Units: uv in glTF texture space ([0,1] spans the image once, v downwards, +u right); a
// footprint is the width in uv units that one shaded pixel covers (the larger of |duv/dx| and
// |duv/dy|). Samples are linear RGBA in [0,1]: a texture holds sRGB-encoded colour (the slots
// base colour, emissive and specular colour) or linear data (every other slot), and sRGB texels
// are decoded before they are filtered, as GPUs do for sRGB formats; alpha is always linear.
// Invariants: levels[0] is the decoded image; levels[k+1] halves levels[k] (rounding up, at
// least 1x1) down to 1x1, each texel the mean light of those it covers, stored in the texture's
// encoding; every level has the same type, CV_8UC3 BGR or CV_8UC4 BGRA.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "holo/core/math.hpp"

namespace holo {

// glTF sampler wrap modes (sampler.wrapS / wrapT).
enum class TextureWrap { Repeat, MirroredRepeat, ClampToEdge };

// glTF sampler filters, reduced to what they decide: bilinear or nearest texels within a level,
// and for minification whether mip levels are used and blended.
struct TextureSampler {
  TextureWrap wrap_u = TextureWrap::Repeat;
  TextureWrap wrap_v = TextureWrap::Repeat;
  bool magnify_linear = true;  // magFilter LINEAR (glTF's default when unset) or NEAREST
  bool minify_linear = true;   // texels within a level: LINEAR or NEAREST
  bool use_mips = true;        // minFilter *_MIPMAP_*: level from the footprint; else level 0 only
  bool blend_mips = true;      // *_MIPMAP_LINEAR: blend the two nearest levels
};

// How the stored bytes encode the values: sRGB colour, or linear data (normals, roughness...).
enum class TextureEncoding { Linear, Srgb };

struct Texture {
  std::vector<cv::Mat> levels;  // the mip chain (see the invariants above)
  TextureSampler sampler;
  TextureEncoding encoding = TextureEncoding::Linear;

  Texture() = default;
  // Builds the mip chain once.
  explicit Texture(cv::Mat image, TextureSampler sampler = {},
                   TextureEncoding encoding = TextureEncoding::Linear);

  const cv::Mat& image() const { return levels.front(); }
  bool empty() const { return levels.empty() || levels.front().empty(); }
};

// The filtered texture value at uv for a pixel covering `footprint` uv units (0: magnified,
// level 0). Wrapping follows the sampler; a non-finite uv or footprint reads texel (0, 0).
// An empty texture reads (1, 1, 1, 1), the neutral value of every glTF texture slot.
vec4 sampleTexture(const Texture& texture, vec2 uv, float footprint);

}  // namespace holo
