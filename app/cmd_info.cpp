// `holopyramid info FILE`: describes an HDR panorama, a glTF model (meshes, triangles,
// materials, bounds) or a recording folder (layout, cameras, frames, intrinsics, poses and the
// first frame's depth coverage).
#include <filesystem>
#include <iostream>
#include <opencv2/core.hpp>
#include <ostream>

#include "command.hpp"
#include "holo/capture/recording.hpp"
#include "holo/capture/recording_source.hpp"
#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/core/material_checks.hpp"

namespace holo::app {
namespace {

int describeRecording(const std::filesystem::path& folder, std::ostream& out) {
  const capture::Recording recording = capture::readRecording(folder);
  out << "folder: " << recording.root.string() << "\n"
      << "type: recording (" << recording.layout << ")\n"
      << "cameras: " << recording.cameras.size() << "\n";
  for (const auto& camera : recording.cameras) {
    const auto& frames = camera.frames;
    const double duration = frames.size() > 1 ? frames.back().timestamp_s - frames.front().timestamp_s : 0.0;
    out << "camera " << camera.id << ": " << camera.name << "\n"
        << "  serial: " << (camera.serial.empty() ? "-" : camera.serial) << "\n"
        << "  frames: " << frames.size() << "\n"
        << "  duration s: " << duration << "\n";
    if (duration > 0) out << "  rate hz: " << static_cast<double>(frames.size() - 1) / duration << "\n";
    // Metres per raw unit, the project's one depth unit; the recording stores PNG units per metre.
    out << "  depth scale: " << 1.0 / camera.depth_scale
        << " m per unit (recording.yaml: " << camera.depth_scale << " PNG units per metre)\n";
    if (camera.model) {
      const Intrinsics& K = camera.model->intrinsics();
      out << "  intrinsics: " << K.width << "x" << K.height << " fx " << K.fx << " fy " << K.fy << " cx "
          << K.cx << " cy " << K.cy << "\n";
      const vec3 position(camera.model->T_world_camera()[3]);
      out << "  position m: " << position.x << " " << position.y << " " << position.z << "\n";
    } else {
      out << "  intrinsics: unknown\n";
    }
    if (frames.empty()) continue;
    // The first frame tells whether the files are what the index says (and how much depth there is).
    const RgbdFrame first = capture::RecordingSource(camera).load(0);
    if (!first.colour.empty()) out << "  colour: " << first.colour.cols << "x" << first.colour.rows << "\n";
    if (!first.depth.empty()) {
      const cv::Mat valid = first.depth > 0;
      double lo = 0, hi = 0;
      cv::minMaxLoc(first.depth, &lo, &hi, nullptr, nullptr, valid);
      out << "  depth: " << first.depth.cols << "x" << first.depth.rows << ", valid "
          << 100.0 * cv::countNonZero(valid) / static_cast<double>(first.depth.total()) << "%, range m " << lo
          << " - " << hi << "\n";
    }
  }
  return 0;
}

void printFeatures(const char* title, const std::vector<GltfFeature>& features) {
  std::cout << title << ": " << features.size() << "\n";
  for (const auto& f : features) {
    std::cout << "  " << f.name << ": " << describe(f.support);
    if (f.required) std::cout << ", required";
    if (f.materials > 0)
      std::cout << " (" << f.materials << (f.materials == 1 ? " material)" : " materials)");
    std::cout << "\n";
  }
}

int describeGltf(const std::filesystem::path& path) {
  const GltfInventory inventory = inspectGltf(path);
  const Model& model = inventory.model;
  const Bounds3 b = model.bounds();
  std::cout << "file: " << path.string() << "\n"
            << "type: glTF model\n"
            << "meshes: " << model.meshes.size() << "\n"
            << "triangles: " << model.triangleCount() << "\n"
            << "textures: " << model.textures.size() << "\n"
            << "bounds min (m): " << b.lo.x << " " << b.lo.y << " " << b.lo.z << "\n"
            << "bounds max (m): " << b.hi.x << " " << b.hi.y << " " << b.hi.z << "\n"
            << "materials: " << model.materials.size() << "\n";
  for (const auto& m : model.materials) {
    std::cout << "  " << (m.name.empty() ? "(unnamed)" : m.name) << ": base colour " << m.base_colour.r << " "
              << m.base_colour.g << " " << m.base_colour.b << ", metallic " << m.metallic << ", roughness "
              << m.roughness;
    if (m.transmissive())
      std::cout << ", transmission " << m.transmission << ", ior " << m.ior << ", thickness " << m.thickness;
    if (m.clearcoat > 0.0f)
      std::cout << ", clearcoat " << m.clearcoat << " (roughness " << m.clearcoat_roughness << ")";
    std::cout << "\n";
  }
  printFeatures("extensions", inventory.extensions);
  printFeatures("texture slots", inventory.texture_slots);
  printFeatures("material properties", inventory.properties);
  const std::vector<MaterialWarning> warnings = checkMaterials(model);
  std::cout << "material warnings: " << warnings.size() << "\n";
  for (const auto& w : warnings) std::cout << "  " << w.message << "\n";
  return 0;
}

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
  if (capture::isRecordingFolder(path)) return describeRecording(path, std::cout);
  std::string ext = path.extension().string();
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".hdr" || ext == ".exr") return describeHdr(path);
  if (ext == ".gltf" || ext == ".glb") return describeGltf(path);
  throw InputError(path.string(), "",
                   "an HDR panorama (.hdr, .exr), a glTF model (.gltf, .glb) or a recording folder",
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
