// The one translation unit that compiles tinygltf's and stb_image_write's implementations (Debian
// ships them header-only for us; libstb.so is not linked).
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include "gltf_tinygltf.hpp"

namespace holo::gltf_detail {

std::string decodeUri(const std::string& uri) {
  return tinygltf::dlib::urldecode(uri);
}

}  // namespace holo::gltf_detail
