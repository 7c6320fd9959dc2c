// `holopyramid info FILE`: describes an HDR panorama (and, as their modules land, glTF models
// and recordings).
#include <filesystem>
#include <iostream>

#include "command.hpp"
#include "holo/core/error.hpp"
#include "holo/core/hdr_io.hpp"
#include "info_gltf.hpp"

namespace holo::app {
namespace {

int describeHdr(const std::filesystem::path& path) {
  const HdrImage hdr = loadHdr(path);
  const LuminanceStats lum = luminanceStats(hdr.pixels);
  std::cout << "file: " << path.string() << "\n"
            << "type: HDR panorama\n"
            << "size: " << hdr.pixels.cols << "x" << hdr.pixels.rows << "\n"
            << "luminance min: " << lum.min << "\n"
            << "luminance max: " << lum.max << "\n"
            << "luminance mean: " << lum.mean << "\n"
            << "clamped nan: " << hdr.repaired.nan << "\n"
            << "clamped inf: " << hdr.repaired.inf << "\n"
            << "clamped negative: " << hdr.repaired.negative << "\n";
  return 0;
}

int describe(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".hdr" || ext == ".exr") return describeHdr(path);
  if (ext == ".gltf" || ext == ".glb") return describeGltf(path);
  throw InputError(path.string(), "", "an HDR panorama (.hdr, .exr) or a glTF model (.gltf, .glb)",
                   "unknown kind of file");
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{"info",
                              [](CLI::App& sub) {
                                auto path = std::make_shared<std::string>();
                                sub.add_option("file", *path, "File to describe")->required();
                                return [path] { return describe(*path); };
                              },
                              "Describe a panorama, model or recording"});

}  // namespace holo::app
