// Confined file access for tinygltf (internal to core). External files (buffers, images) a glTF
// names are read only from inside the glTF's own folder: a relic from outside must not make the
// appliance read /etc/passwd, a file next to the program (tinygltf also searches the working
// directory) or one a symlink leads to. URIs are percent-decoded before they are checked; no
// absolute path, no '..' and no symlink may lead out of the folder.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "gltf_tinygltf.hpp"

namespace holo::gltf_detail {

// Parses `size` bytes (binary glTF when `binary`, JSON otherwise) into `gltf` through `loader`,
// with tinygltf's file system replaced by one confined to `folder` (empty: a glTF from memory,
// nothing external is read; the loader never writes). Returns tinygltf's verdict, its messages in
// `err` and `warn`. Throws InputError naming `file` and the first buffers[i].uri or images[i].uri
// that pointed outside, or when `folder` cannot be resolved.
bool loadConfined(tinygltf::TinyGLTF& loader, tinygltf::Model& gltf, std::string& err, std::string& warn,
                  const unsigned char* bytes, std::size_t size, bool binary,
                  const std::filesystem::path& folder, const std::string& file);

}  // namespace holo::gltf_detail
