// glTF relics: binary glTF bytes through tinygltf and our accessor reading (index and attribute
// accessors, normalised integer components as KHR_mesh_quantization uses, node hierarchies,
// embedded textures). Only holo::InputError may come out; anything else is a finding.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/log.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  holo::initLogging(holo::LogLevel::Off);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const holo::Model model =
        holo::loadGlbFromMemory(std::vector<std::uint8_t>(data, data + size), "fuzz.glb");
    for (const auto& mesh : model.meshes)
      for (const auto& t : mesh.triangles)
        if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size())
          __builtin_trap();  // the loader promises every index < positions.size()
  } catch (const holo::InputError&) {
  }
  return 0;
}
