// Recordings: a folder made from one input (recording.yaml, cam0/associations.txt, a colour and
// a depth frame, separated by "\n=====\n"), read with readRecording and replayed frame by frame
// with RecordingSource::load (PNG/JPEG decoding, 16-bit depth to metres). Only holo::InputError
// may come out.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz_files.hpp"
#include "holo/capture/recording.hpp"
#include "holo/capture/recording_source.hpp"
#include "holo/core/error.hpp"
#include "holo/core/log.hpp"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  holo::initLogging(holo::LogLevel::Off);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  const fs::path root = holo::fuzz::scratchDir() / "recording";
  fs::remove_all(root);
  const auto parts = holo::fuzz::splitInput(data, size, "\n=====\n", 4);
  const char* names[] = {"recording.yaml", "cam0/associations.txt", "cam0/rgb/0.png", "cam0/depth/0.png"};
  for (std::size_t i = 0; i < parts.size(); ++i) holo::fuzz::writeBytes(root / names[i], parts[i]);
  try {
    const holo::capture::Recording recording = holo::capture::readRecording(root);
    for (const auto& camera : recording.cameras) {
      const holo::capture::RecordingSource source(camera);
      for (std::size_t i = 0; i < source.frameCount() && i < 4; ++i) (void)source.load(i);
    }
  } catch (const holo::InputError&) {
  }
  return 0;
}
