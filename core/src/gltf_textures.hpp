// glTF images and textures into holo::Texture (internal to core).
//
// Images are decoded by OpenCV (libpng, libjpeg-turbo: kept and patched by Debian), not by the
// stb_image copy tinygltf would compile: the fuzzer found stb's JPEG Huffman tables writing past
// their end. decodeTexture is the image loader tinygltf calls for every image; TextureTable turns
// the decoded images and their samplers into Model::textures as materials ask for them.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "gltf_tinygltf.hpp"
#include "holo/core/texture.hpp"

namespace holo::gltf_detail {

// tinygltf's LoadImageDataFunction: PNG or JPEG only, at most kMaxGltfTextureSide pixels a side,
// stored with its channels in glTF's order (RGB or RGBA; gray stays gray), 8 or 16 bits. OpenCV
// refuses images above OPENCV_IO_MAX_IMAGE_PIXELS before allocating (the kiosk unit sets it).
// False, with the reason appended to `err`, otherwise.
bool decodeTexture(tinygltf::Image* image, int image_index, std::string* err, std::string* warn,
                   int req_width, int req_height, const unsigned char* bytes, int size, void* user);

// (glTF texture index, encoding) -> index into `textures`, each decoded (mip chain built) once.
// A texture that a colour slot and a data slot both use is built once per encoding.
class TextureTable {
 public:
  TextureTable(const tinygltf::Model& gltf, const std::string& file, std::vector<Texture>& textures);

  // The index in `textures` of glTF texture `gltf_texture` with `encoding`, built on first use;
  // -1 when its image is missing or undecodable (counted in "glTF/Textures ignored" and warned).
  // InputError for a texture or sampler index out of range.
  int index(int gltf_texture, TextureEncoding encoding);

 private:
  const tinygltf::Model& gltf_;
  const std::string& file_;
  std::vector<Texture>& textures_;
  std::vector<std::array<int, 2>> built_;  // per glTF texture: [linear, sRGB] index or -1
};

}  // namespace holo::gltf_detail
