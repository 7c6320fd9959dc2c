#include "gltf_parse.hpp"

#include <cctype>

#include "gltf_confined_files.hpp"
#include "gltf_extensions.hpp"
#include "gltf_textures.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/gltf_limits.hpp"
#include "holo/core/log.hpp"

namespace holo::gltf_detail {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string firstLine(const std::string& s) {
  std::string out = s.substr(0, s.find('\n'));
  return out.empty() ? "unknown error" : out;
}

[[noreturn]] void loadFailed(const std::string& file, const std::string& err, bool draco) {
  if (draco)
    throw InputError(file, "extensionsRequired", "meshes without Draco compression (no Draco decoder)",
                     kDraco);
  const std::string low = lower(err);
  if (low.find("not found") != std::string::npos) {
    // tinygltf reports a missing external file by name only; its extension tells which it was.
    const bool image = low.find(".png") != std::string::npos || low.find(".jp") != std::string::npos ||
                       low.find("image") != std::string::npos;
    throw InputError(file, image ? "images" : "buffers", "every external file the glTF names, next to it",
                     firstLine(err));
  }
  const std::string field = low.find("buffer") != std::string::npos  ? "buffers"
                            : low.find("image") != std::string::npos ? "images"
                                                                     : "";
  throw InputError(file, field, "a valid glTF 2.0 file", firstLine(err));
}

// True when the raw JSON chunk names the Draco extension (tinygltf may fail before we look).
bool mentionsDraco(const std::string& bytes) {
  return bytes.find(kDraco) != std::string::npos;
}

}  // namespace

std::string formatExtension(const fs::path& path) {
  return lower(path.extension().string());
}

tinygltf::Model parseGltfFile(const fs::path& path) {
  const std::string file = path.string();
  if (!fs::exists(path)) throw InputError(file, "", "an existing .gltf or .glb file", "not found");
  const std::string ext = formatExtension(path);
  if (ext != ".gltf" && ext != ".glb") throw InputError(file, "", "a .gltf or .glb file", ext);
  if (const auto bytes_on_disk = fs::file_size(path); bytes_on_disk > kMaxGltfFileBytes)
    throw InputError(file, "", "a glTF file of at most " + std::to_string(kMaxGltfFileBytes >> 20) + " MiB",
                     std::to_string(bytes_on_disk >> 20) + " MiB");
  const std::string bytes = readFile(path);
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(decodeTexture, nullptr);
  tinygltf::Model gltf;
  std::string err, warn;
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const bool ok = loadConfined(loader, gltf, err, warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                               bytes.size(), ext == ".glb", folder, file);
  if (!warn.empty()) HOLO_LOG_DEBUG("{}: tinygltf: {}", file, firstLine(warn));
  if (!ok) loadFailed(file, err, mentionsDraco(bytes));
  return gltf;
}

tinygltf::Model parseGlb(const std::vector<std::uint8_t>& glb, const std::string& origin) {
  if (glb.size() > kMaxGltfFileBytes)
    throw InputError(origin, "", "a glTF file of at most " + std::to_string(kMaxGltfFileBytes >> 20) + " MiB",
                     std::to_string(glb.size() >> 20) + " MiB");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(decodeTexture, nullptr);
  tinygltf::Model gltf;
  std::string err, warn;
  if (!loadConfined(loader, gltf, err, warn, glb.data(), glb.size(), true, {}, origin))
    loadFailed(origin, err, mentionsDraco(std::string(glb.begin(), glb.end())));
  return gltf;
}

}  // namespace holo::gltf_detail
