// Atomic file writes: data goes to "PATH.tmp-PID" in the same folder, is flushed, then renamed
// over PATH, so readers see either the old file or the new one, never half of one.
#pragma once

#include <filesystem>
#include <functional>
#include <string_view>

namespace holo {

void writeFileAtomically(const std::filesystem::path& path, std::string_view contents);
// For writers that need a file name (OpenCV, OpenEXR): `write` receives the temporary path.
void writeAtomically(const std::filesystem::path& path,
                     const std::function<void(const std::filesystem::path& tmp)>& write);
std::string readFile(const std::filesystem::path& path);  // throws InputError when unreadable

}  // namespace holo
