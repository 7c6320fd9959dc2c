#include "gltf_confined_files.hpp"

#include <system_error>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/gltf_limits.hpp"

namespace holo::gltf_detail {

namespace fs = std::filesystem;

namespace {

// The state behind tinygltf's file callbacks for one load; the first URI that points outside is
// kept for the error.
struct ExternalFileScope {
  std::string base;    // the search folder given to tinygltf: canonical, or empty (nothing external)
  fs::path folder;     // the same folder as a path
  std::string escape;  // the first URI that led outside `folder`
};

// The file `joined` (tinygltf's search folder + "/" + the decoded URI) resolves to, when it lies
// inside the glTF's folder; empty otherwise (tinygltf's other search folder, ".", is never used).
fs::path resolveInside(ExternalFileScope& scope, const std::string& joined) {
  const std::string prefix = scope.base.empty() || scope.base.back() == '/' ? scope.base : scope.base + "/";
  if (scope.base.empty() || joined.rfind(prefix, 0) != 0) {
    if (scope.base.empty() && scope.escape.empty()) scope.escape = joined;  // no folder at all
    return {};
  }
  const std::string uri = joined.substr(prefix.size());
  std::error_code error;
  const fs::path resolved = fs::weakly_canonical(scope.folder / uri, error);
  const fs::path inside = resolved.lexically_relative(scope.folder);
  const bool escapes =
      uri.empty() || fs::path(uri).is_absolute() || error || inside.empty() || *inside.begin() == "..";
  if (escapes) {
    if (scope.escape.empty()) scope.escape = uri;
    return {};
  }
  return resolved;
}

bool externalFileExists(const std::string& joined, void* user) {
  const fs::path file = resolveInside(*static_cast<ExternalFileScope*>(user), joined);
  std::error_code error;
  return !file.empty() && fs::is_regular_file(file, error);
}

std::string keepFilePath(const std::string& path, void*) {
  return path;  // no ~ or $VAR expansion in a URI
}

bool readExternalFile(std::vector<unsigned char>* out, std::string* err, const std::string& joined,
                      void* user) {
  const fs::path file = resolveInside(*static_cast<ExternalFileScope*>(user), joined);
  std::error_code error;
  const auto bytes = file.empty() ? 0 : fs::file_size(file, error);
  if (file.empty() || error || bytes > kMaxGltfFileBytes) {
    *err =
        "outside the glTF's folder, unreadable or over " + std::to_string(kMaxGltfFileBytes >> 20) + " MiB";
    return false;
  }
  const std::string text = readFile(file);
  out->assign(text.begin(), text.end());
  return true;
}

bool refuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  *err = "the loader writes no files";
  return false;
}

}  // namespace

bool loadConfined(tinygltf::TinyGLTF& loader, tinygltf::Model& gltf, std::string& err, std::string& warn,
                  const unsigned char* bytes, std::size_t size, bool binary, const fs::path& folder,
                  const std::string& file) {
  ExternalFileScope scope;
  if (!folder.empty()) {
    std::error_code error;
    scope.folder = fs::canonical(folder, error);
    if (error) throw InputError(file, "", "a glTF in a readable folder", error.message());
    scope.base = scope.folder.string();
  }
  loader.SetFsCallbacks({externalFileExists, keepFilePath, readExternalFile, refuseWrite, &scope});
  const auto length = static_cast<unsigned int>(size);
  const bool ok = binary ? loader.LoadBinaryFromMemory(&gltf, &err, &warn, bytes, length, scope.base)
                         : loader.LoadASCIIFromString(
                               &gltf, &err, &warn, reinterpret_cast<const char*>(bytes), length, scope.base);
  if (scope.escape.empty()) return ok;
  // Images that fail to load stay in the model with their URI; a failing buffer ends the load.
  std::string field = "buffers[" + std::to_string(gltf.buffers.size()) + "].uri";
  for (std::size_t i = 0; i < gltf.images.size(); ++i)
    if (!gltf.images[i].uri.empty() && gltf.images[i].image.empty() &&
        decodeUri(gltf.images[i].uri) == scope.escape)
      field = "images[" + std::to_string(i) + "].uri";
  throw InputError(file, field,
                   folder.empty() ? "only embedded data in a glTF read from memory"
                                  : "a relative path inside the glTF's folder " + scope.base +
                                        " (no absolute path, no '..' or symlink leading out of it)",
                   scope.escape);
}

}  // namespace holo::gltf_detail
