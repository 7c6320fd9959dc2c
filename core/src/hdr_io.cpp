#include "holo/core/hdr_io.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <string_view>

#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/log.hpp"

namespace holo {

namespace fs = std::filesystem;

namespace {

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

constexpr int kMaxExrSide = 16384;

std::string sizeText(std::int64_t width, std::int64_t height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

// The panorama's size as its header states it, checked before any pixel is allocated.
void checkPanoramaSize(const fs::path& path, const std::string& field, std::int64_t width,
                       std::int64_t height) {
  if (width <= 0 || height <= 0)
    throw InputError(path.string(), field, "a positive image size", sizeText(width, height));
  if (width * height > static_cast<std::int64_t>(kMaxPanoramaPixels))
    throw InputError(
        path.string(), field,
        "at most " + std::to_string(kMaxPanoramaPixels) + " pixels (8192x4096; downsample the panorama)",
        sizeText(width, height));
}

// OpenCV's Radiance decoder takes a file starting with either of these.
bool hasRadianceSignature(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char start[10] = {};
  in.read(start, sizeof start);
  const std::string_view text(start, static_cast<std::size_t>(in.gcount()));
  return text.rfind("#?RADIANCE", 0) == 0 || text.rfind("#?RGBE", 0) == 0;
}

// A Radiance file's resolution line ("-Y 4096 +X 8192", after the header's blank line), or
// nothing when the header does not parse (OpenCV then reports the file as unreadable).
std::optional<std::pair<std::int64_t, std::int64_t>> radianceSize(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  bool blank_seen = false;
  // Headers are a handful of short lines; a file that has no blank line early is not one.
  for (int lines = 0; lines < 128 && std::getline(in, line); ++lines) {
    if (!blank_seen) {
      blank_seen = line.empty();
      continue;
    }
    char first[3] = {}, second[3] = {};
    long long a = 0, b = 0;
    if (std::sscanf(line.c_str(), "%2s %lld %2s %lld", first, &a, second, &b) != 4) return std::nullopt;
    if (first[1] == 'Y' && second[1] == 'X') return std::pair<std::int64_t, std::int64_t>{b, a};
    if (first[1] == 'X' && second[1] == 'Y') return std::pair<std::int64_t, std::int64_t>{a, b};
    return std::nullopt;
  }
  return std::nullopt;
}

// OpenEXR 3.1 allocates a header attribute's value at the size the file states, before reading
// it: a damaged 3.6 KB file stating a 1.6 GB string attribute made it allocate 1.7 GB and spend
// seconds failing (fuzz_hdr). Every attribute's stated size is checked here against the bytes
// the file holds, before OpenEXR reads the header.
void checkExrAttributes(const fs::path& path) {
  std::error_code error;
  const auto file_bytes = static_cast<std::int64_t>(fs::file_size(path, error));
  std::ifstream in(path, std::ios::binary);
  unsigned char start[8];
  if (error || !in.read(reinterpret_cast<char*>(start), sizeof start))
    throw InputError(path.string(), "", "an OpenEXR file", "shorter than its 8-byte start");
  const auto little = [](const unsigned char* b) {
    return static_cast<std::uint32_t>(b[0]) | static_cast<std::uint32_t>(b[1]) << 8 |
           static_cast<std::uint32_t>(b[2]) << 16 | static_cast<std::uint32_t>(b[3]) << 24;
  };
  const std::uint32_t flags = little(start + 4);
  const bool multipart = (flags & 0x1000) != 0;
  const std::size_t max_name = (flags & 0x400) != 0 ? 255 : 31;
  const auto truncated = [&path] {
    throw InputError(path.string(), "header", "a complete OpenEXR header", "the file ends inside it");
  };
  const auto readName = [&](std::string& name) {
    name.clear();
    for (char c; in.get(c);) {
      if (c == '\0') return;
      if (name.size() == max_name)
        throw InputError(path.string(), "header", "names of at most " + std::to_string(max_name) + " bytes",
                         "'" + name + "...'");
      name += c;
    }
    truncated();
  };
  std::string name, type;
  for (bool first = true;; first = false) {
    int attributes = 0;
    for (readName(name); !name.empty(); readName(name), ++attributes) {
      readName(type);
      unsigned char size_bytes[4];
      if (!in.read(reinterpret_cast<char*>(size_bytes), sizeof size_bytes)) truncated();
      const auto size = static_cast<std::int32_t>(little(size_bytes));
      const std::int64_t left = file_bytes - static_cast<std::int64_t>(in.tellg());
      if (size < 0 || size > left)
        throw InputError(path.string(), "header attribute '" + name + "'",
                         "a value within the " + std::to_string(left) + " bytes left in the file",
                         std::to_string(size) + " bytes");
      in.seekg(size, std::ios::cur);
    }
    if (!multipart || (attributes == 0 && !first)) return;  // a multi-part file ends with an empty header
  }
}

cv::Mat readExr(const fs::path& path) {
  checkExrAttributes(path);
  // OpenEXR allocates its line offset table from the data window when it opens a file, before
  // checkPanoramaSize can look: no side beyond 16384 (which no panorama within the limit needs).
  static const bool sides_limited = [] {
    Imf::Header::setMaxImageSize(kMaxExrSide, kMaxExrSide);
    Imf::Header::setMaxTileSize(kMaxExrSide, kMaxExrSide);
    return true;
  }();
  (void)sides_limited;
  Imf::InputFile file(path.c_str());
  const auto& header = file.header();
  const auto window = header.dataWindow();
  checkPanoramaSize(path, "dataWindow", std::int64_t{window.max.x} - window.min.x + 1,
                    std::int64_t{window.max.y} - window.min.y + 1);
  const int width = window.max.x - window.min.x + 1;
  const int height = window.max.y - window.min.y + 1;
  const auto& channels = header.channels();
  const bool rgb = channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B");
  const bool grey = channels.findChannel("Y") != nullptr;
  if (!rgb && !grey) throw InputError(path.string(), "channels", "R, G and B (or Y) channels");

  cv::Mat bgr(height, width, CV_32FC3, cv::Scalar::all(0));
  auto* base =
      reinterpret_cast<char*>(bgr.ptr<float>()) -
      (static_cast<std::ptrdiff_t>(window.min.x) + static_cast<std::ptrdiff_t>(window.min.y) * width) *
          static_cast<std::ptrdiff_t>(sizeof(float) * 3);
  const std::size_t xs = sizeof(float) * 3, ys = xs * static_cast<std::size_t>(width);
  Imf::FrameBuffer frame;
  if (rgb) {
    frame.insert("B", Imf::Slice(Imf::FLOAT, base, xs, ys));
    frame.insert("G", Imf::Slice(Imf::FLOAT, base + sizeof(float), xs, ys));
    frame.insert("R", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));
  } else {
    frame.insert("Y", Imf::Slice(Imf::FLOAT, base, xs, ys));
  }
  file.setFrameBuffer(frame);
  file.readPixels(window.min.y, window.max.y);
  if (!rgb) {
    bgr.forEach<cv::Vec3f>([](cv::Vec3f& p, const int*) { p[1] = p[2] = p[0]; });
  }
  return bgr;
}

void writeExr(const fs::path& path, const cv::Mat& bgr) {
  Imf::Header header(bgr.cols, bgr.rows);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  cv::Mat contiguous = bgr.isContinuous() ? bgr : bgr.clone();
  auto* base = const_cast<char*>(reinterpret_cast<const char*>(contiguous.ptr<float>()));
  const std::size_t xs = sizeof(float) * 3, ys = xs * static_cast<std::size_t>(bgr.cols);
  Imf::FrameBuffer frame;
  frame.insert("B", Imf::Slice(Imf::FLOAT, base, xs, ys));
  frame.insert("G", Imf::Slice(Imf::FLOAT, base + sizeof(float), xs, ys));
  frame.insert("R", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xs, ys));
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(frame);
  file.writePixels(bgr.rows);
}

}  // namespace

HdrImage loadHdr(const fs::path& path) {
  if (!fs::exists(path)) throw InputError(path.string(), "", "an existing HDR panorama file", "no such file");
  const std::string ext = lowerExtension(path);
  HdrImage out;
  try {
    if (ext == ".exr") {
      out.pixels = readExr(path);
    } else if (ext == ".hdr" || ext == ".pic") {
      // imread picks its decoder by the content, not the name: without this a file named .hdr
      // reaches OpenCV's JPEG 2000, TIFF, WebP... decoders (fuzz_hdr reached OpenJPEG's).
      if (!hasRadianceSignature(path))
        throw InputError(path.string(), "", "a Radiance RGBE (.hdr) image starting with #?RADIANCE or #?RGBE",
                         "another format");
      if (const auto size = radianceSize(path))
        checkPanoramaSize(path, "resolution", size->first, size->second);
      out.pixels = cv::imread(path.string(), cv::IMREAD_ANYDEPTH | cv::IMREAD_COLOR);
      if (out.pixels.empty())
        throw InputError(path.string(), "", "a Radiance RGBE (.hdr) image", "unreadable");
      out.pixels.convertTo(out.pixels, CV_32FC3);
    } else {
      throw InputError(path.string(), "extension", ".hdr or .exr", ext.empty() ? "none" : ext);
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path.string(), "", "a readable HDR image", e.what());
  }
  if (out.pixels.channels() != 3) throw InputError(path.string(), "channels", "3 colour channels");
  out.repaired = sanitizeRadiance(out.pixels);
  if (out.repaired.total() > 0)
    HOLO_LOG_WARN("{}: clamped {} NaN, {} Inf and {} negative values", path.string(), out.repaired.nan,
                  out.repaired.inf, out.repaired.negative);
  return out;
}

void saveHdr(const fs::path& path, const cv::Mat& bgr32f) {
  CV_Assert(bgr32f.type() == CV_32FC3);
  const std::string ext = lowerExtension(path);
  writeAtomically(path, [&](const fs::path& tmp) {
    if (ext == ".exr") {
      writeExr(tmp, bgr32f);
    } else if (ext == ".hdr") {
      // OpenCV picks the encoder from the extension, so the temporary keeps ".hdr" at the end.
      if (!cv::imwrite(tmp.string(), bgr32f)) throw Error("could not write " + path.string());
    } else {
      throw InputError(path.string(), "extension", ".exr or .hdr", ext);
    }
  });
}

LuminanceStats luminanceStats(const cv::Mat& bgr32f) {
  LuminanceStats s;
  if (bgr32f.empty()) return s;
  s.min = 1e30f;
  double sum = 0;
  for (int y = 0; y < bgr32f.rows; ++y)
    for (int x = 0; x < bgr32f.cols; ++x) {
      const float l = luminance(rgbAt(bgr32f, x, y));
      s.min = std::min(s.min, l);
      s.max = std::max(s.max, l);
      sum += l;
    }
  s.mean = static_cast<float>(sum / static_cast<double>(bgr32f.total()));
  return s;
}

}  // namespace holo
