// tinygltf as this build configures it (internal to core). Every translation unit that uses
// tinygltf includes it through this header, so all of them see the same declarations: no
// stb_image (textures are decoded by OpenCV, see gltf_textures.hpp) and stb_image_write included
// here rather than by tinygltf, only where gltf_tinygltf.cpp compiles the implementations.
#pragma once

#include <string>

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wcast-align"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wsign-compare"
#ifdef TINYGLTF_IMPLEMENTATION
#include <stb_image_write.h>
#endif
#include <tiny_gltf.h>
#pragma GCC diagnostic pop

namespace holo::gltf_detail {

// `uri` decoded as tinygltf decodes a URI before it opens the file (percent-encoding, '+').
std::string decodeUri(const std::string& uri);

}  // namespace holo::gltf_detail
