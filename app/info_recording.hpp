// `holopyramid info` for a recording folder (any layout capture/recording.hpp reads).
#pragma once

#include <filesystem>
#include <iosfwd>

namespace holo::app {

// Writes layout, cameras (name, serial, frame count, duration, rate, intrinsics, pose) and the
// first frame's depth coverage to `out`. Throws InputError for a malformed recording.
int describeRecording(const std::filesystem::path& folder, std::ostream& out);

}  // namespace holo::app
