#include "holo/core/files.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <fstream>
#include <sstream>

#include "holo/core/error.hpp"

namespace holo {

namespace fs = std::filesystem;

namespace {
// The temporary keeps the final extension, because some writers choose the format from it.
fs::path temporaryFor(const fs::path& path) {
  fs::path tmp = path;
  tmp.replace_filename(path.stem().string() + ".tmp-" + std::to_string(::getpid()) +
                       path.extension().string());
  return tmp;
}

void syncFile(const fs::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}
}  // namespace

void writeAtomically(const fs::path& path, const std::function<void(const fs::path& tmp)>& write) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  const fs::path tmp = temporaryFor(path);
  try {
    write(tmp);
    syncFile(tmp);
    fs::rename(tmp, path);
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw;
  }
}

void writeFileAtomically(const fs::path& path, std::string_view contents) {
  writeAtomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.flush();
    if (!out) throw Error("could not write " + tmp.string());
  });
}

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "a readable file", "cannot open");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace holo
